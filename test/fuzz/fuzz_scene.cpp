// parseSceneText on a scene file's YAML (the form a set's provenance stores; files need not exist): either a
// typed error naming the problem, or a scene whose values satisfy the reader's checks and whose YAML form
// reads back to the same text.
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const de::scene_file::SceneDescription s =
        de::scene_file::parseSceneText(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
    DE_FUZZ_CHECK(s.units > 0.0 && std::isfinite(s.units));
    DE_FUZZ_CHECK(s.material.young > 0.0 && s.material.poisson > -1.0 && s.material.poisson < 0.5);
    DE_FUZZ_CHECK(s.stamp.radius > 0.0 && s.stamp.resolution >= 2 && s.tool.radius > 0.0);
    DE_FUZZ_CHECK(s.procedural || s.fixed);
    const std::string yaml = de::scene_file::sceneYaml(s);
    DE_FUZZ_CHECK(de::scene_file::sceneYaml(de::scene_file::parseSceneText(yaml, "again.yaml")) == yaml);
  } catch (const de::Error&) {
  }
  return 0;
}
