// readVtk on a legacy .vtk file's bytes (the first byte picks legacy or XML .vtu for the rest).
#include <sstream>
#include <string>

#include "deformation_enrichment/mesh/vtk_io.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool xml = data[0] & 1;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), std::ios::in | std::ios::binary);
  try {
    de::fuzz::checkVolumeMesh(de::mesh::readVtk(in, xml, xml ? "fuzz.vtu" : "fuzz.vtk"));
  } catch (const de::IoError&) {
  }
  return 0;
}
