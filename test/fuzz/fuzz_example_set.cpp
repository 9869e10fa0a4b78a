// parseExampleSet on a manifest and a stamp blob: the input is the manifest text, a NUL byte, then the
// blob. A mutated blob almost never matches the manifest's checksum, so every input is tried twice:
// as it is, and with the manifest's size_bytes / fnv1a64 set to the blob's, which lets the fuzzer reach
// the per-example checks behind the checksum.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;
namespace ex = deformation_enrichment::examples;

namespace {

void load(std::string_view manifest, std::string_view blob) {
  try {
    const ex::ExampleSet set = ex::parseExampleSet(manifest, blob, "fuzz");
    DE_FUZZ_CHECK(!set.examples.empty());
    for (const ex::Example& e : set.examples) {
      DE_FUZZ_CHECK(ex::exampleProblem(e).empty());
      DE_FUZZ_CHECK(e.stamp.size() == set.examples[0].stamp.size());
    }
  } catch (const de::IoError&) {
  }
}

// The manifest with the blob's true size and checksum, or empty when it has no stamp_blob object.
std::string withTrueChecksum(std::string_view manifest, std::string_view blob) {
  nlohmann::json json = nlohmann::json::parse(manifest.begin(), manifest.end(), nullptr, false);
  if (!json.is_object() || !json.contains("stamp_blob") || !json["stamp_blob"].is_object()) return {};
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016" PRIx64, ex::fnv1a64(blob.data(), blob.size()));
  json["stamp_blob"]["size_bytes"] = blob.size();
  json["stamp_blob"]["fnv1a64"] = hash;
  return json.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t split = std::min(input.find('\0'), input.size());
  const std::string_view manifest = input.substr(0, split);
  const std::string_view blob = split < input.size() ? input.substr(split + 1) : std::string_view();
  load(manifest, blob);
  const std::string repaired = withTrueChecksum(manifest, blob);
  if (!repaired.empty()) load(repaired, blob);
  return 0;
}
