// readTetGen on a .node and an .ele text: the input is the .node text, a NUL byte, then the .ele text.
#include <algorithm>
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const char* text = reinterpret_cast<const char*>(data);
  const char* split = std::find(text, text + size, '\0');
  std::istringstream node(std::string(text, split));
  std::istringstream ele(split == text + size ? std::string() : std::string(split + 1, text + size));
  try {
    const de::mesh::TetGenMesh read = de::mesh::readTetGen(node, ele, "fuzz");
    de::mesh::validate(read.mesh);  // positive volumes, indices in range, finite: what readTetGen promises
    DE_FUZZ_CHECK(read.region.size() == read.mesh.numTets());
    DE_FUZZ_CHECK(read.reorientedTets >= 0 && read.reorientedTets <= read.mesh.numTets());
  } catch (const de::IoError&) {
  }
  return 0;
}
