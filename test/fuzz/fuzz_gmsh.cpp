// readGmsh on a .msh file's bytes (2.2 and 4.1, ASCII and binary).
#include <sstream>
#include <string>

#include "deformation_enrichment/mesh/gmsh_io.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::in | std::ios::binary);
  try {
    de::fuzz::checkVolumeMesh(de::mesh::readGmsh(in, "fuzz.msh"));
  } catch (const de::IoError&) {
  }
  return 0;
}
