// readObj on an OBJ file's bytes (readTriangleMesh's .obj reader).
#include "deformation_enrichment/mesh/obj_reader.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  de::fuzz::readMeshBytes(de::mesh::readObj, data, size, "fuzz.obj");
  return 0;
}
