// readPlan on a plan / contacts CSV text.
#include <cmath>
#include <sstream>
#include <string>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/error.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const auto plan = de::acquisition::readPlan(in, "fuzz.csv");
    DE_FUZZ_CHECK(!plan.empty());
    for (const auto& entry : plan) {
      DE_FUZZ_CHECK(entry.point.allFinite() && entry.drag.allFinite() && std::isfinite(entry.depth));
      DE_FUZZ_CHECK(entry.depth >= 0.0);
    }
  } catch (const de::IoError&) {
  }
  return 0;
}
