#pragma once
// On-disk example sets. A set is a directory holding
//   manifest.json  format name and version, package version, units, scene/material metadata, one entry
//                  per example (contact, frame, descriptors, radius, stamp size, pattern, scene id) and
//                  the blob's size and FNV-1a 64 checksum;
//   stamps.bin     every stamp's float32 values (little-endian), row-major rows x cols x 3, examples in
//                  manifest order, no padding.
// Both files are written to temporaries and renamed, so an interrupted write never leaves a half set
// under the final names. The loader checks everything and throws IoError naming the file and problem.
#include <cstdint>
#include <string>
#include <string_view>

#include "deformation_enrichment/examples/example.hpp"

namespace deformation_enrichment::examples {

constexpr int kExampleSetFormatVersion = 1;
constexpr const char* kExampleSetFormatName = "deformation_enrichment.example_set";
constexpr const char* kPackageVersion = "0.1.0";
constexpr const char* kManifestFile = "manifest.json";
constexpr const char* kStampBlobFile = "stamps.bin";

/// FNV-1a 64-bit hash of a byte range (the stamp blob's checksum).
std::uint64_t fnv1a64(const void* data, std::size_t size);

/// Writes `set` into `directory` (created if missing). Throws InvalidInputError for an invalid example
/// (validateExample), an empty set or stamps of different size or radius, IoError when files cannot be
/// written.
void saveExampleSet(const ExampleSet& set, const std::string& directory);

/// Reads and validates a set. Throws IoError ("<file>: <problem>") for a missing or unparsable manifest,
/// wrong format name or version, missing or mistyped fields, non-finite numbers, wrong units, descriptor
/// sizes that do not match their orders, inconsistent descriptor layouts across examples, a blob whose
/// size or checksum does not match, non-finite stamp values, non-positive radius, non-orthonormal frame,
/// stamps whose size or radius differ between examples (eq. 16 blends them node by node).
ExampleSet loadExampleSet(const std::string& directory);

/// The same from the contents of the two files (loadExampleSet reads them and calls this); `directory`
/// names the files in error messages.
ExampleSet parseExampleSet(std::string_view manifest, std::string_view blob, const std::string& directory);

}  // namespace deformation_enrichment::examples
