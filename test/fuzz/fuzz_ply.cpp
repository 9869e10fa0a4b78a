// readPly on a PLY file's bytes (readTriangleMesh's .ply reader).
#include "deformation_enrichment/mesh/ply_reader.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  de::fuzz::readMeshBytes(de::mesh::readPly, data, size, "fuzz.ply");
  return 0;
}
