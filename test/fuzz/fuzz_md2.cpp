// readMd2 on an MD2 file (the reader takes a path, so the input goes through a scratch file).
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/md2_reader.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const de::fuzz::ScratchFile scratch(".md2");
  try {
    const de::shape_space::Md2Animation animation = de::shape_space::readMd2(scratch.write(data, size));
    DE_FUZZ_CHECK(!animation.frames.empty() && animation.frames.size() == animation.frameNames.size());
    for (const auto& frame : animation.frames) {
      de::mesh::validate(frame, false);  // documented: every frame passes it
      DE_FUZZ_CHECK(frame.triangles == animation.frames[0].triangles);
    }
  } catch (const de::IoError&) {
  }
  return 0;
}
