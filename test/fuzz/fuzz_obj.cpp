// readObj on an OBJ file's bytes (readTriangleMesh's .obj reader).
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/obj_reader.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    de::fuzz::checkTriangleMesh(de::mesh::readObj(in, "fuzz.obj"));
  } catch (const de::IoError&) {
  }
  return 0;
}
