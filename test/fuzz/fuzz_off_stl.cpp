// readTriangleMesh on OFF or STL bytes (the core's OFF reader, CGAL's STL reader; the first byte picks the format).
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const de::mesh::SurfaceFormat format = data[0] & 1 ? de::mesh::SurfaceFormat::Stl : de::mesh::SurfaceFormat::Off;
  de::fuzz::readMeshBytes([format](std::istream& in, const std::string& name) { return de::mesh::readTriangleMesh(in, format, name); },
                          data + 1, size - 1, format == de::mesh::SurfaceFormat::Stl ? "fuzz.stl" : "fuzz.off");
  return 0;
}
