// Round trip and rejection of corrupt example sets: every corruption gives an IoError naming the problem.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"

namespace de = deformation_enrichment;
namespace ex = deformation_enrichment::examples;
namespace fs = std::filesystem;

namespace {

ex::Example makeExample(int seed, int rows = 8, int cols = 6) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ex::Example e;
  e.contact = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.05;
  e.frame = Eigen::AngleAxisd(u(rng) * 3.0, Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  e.rho = de::hermite::MomentList(0, 3, 1);
  e.mu = de::hermite::MomentList(1, 2, 3);
  for (Eigen::Index i = 0; i < e.rho.values().size(); ++i) e.rho.values()[i] = u(rng);
  for (Eigen::Index i = 0; i < e.mu.values().size(); ++i) e.mu.values()[i] = u(rng) * 1e-3;
  e.stamp.create(rows, cols, CV_32FC3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) e.stamp.at<cv::Vec3f>(r, c) = cv::Vec3f(float(u(rng)), float(u(rng)), float(u(rng))) * 1e-3f;
  e.stampRadius = 0.0125;
  e.pattern.indentDepth = 0.004;
  e.pattern.drag = Eigen::Vector3d(0.002, -0.001, 0.0);
  e.sceneId = "slab";
  return e;
}

ex::ExampleSet makeSet() {
  ex::ExampleSet set;
  set.metadata.scene = "slab";
  set.metadata.material = {{"young_modulus", 3000.0}, {"poisson_ratio", 0.45}};
  set.metadata.description = "unit test set";
  set.examples = {makeExample(1), makeExample(2), makeExample(3)};
  return set;
}

class ExampleSetIo : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("de_example_set_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    ex::saveExampleSet(makeSet(), dir_.string());
  }
  void TearDown() override { fs::remove_all(dir_); }

  nlohmann::json manifest() const {
    std::ifstream in(dir_ / ex::kManifestFile);
    return nlohmann::json::parse(in);
  }
  void writeManifest(const nlohmann::json& m) const {
    std::ofstream out(dir_ / ex::kManifestFile, std::ios::trunc);
    out << m.dump(1);
  }
  std::vector<char> blob() const {
    std::ifstream in(dir_ / ex::kStampBlobFile, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
  }
  void writeBlob(const std::vector<char>& b) const {
    std::ofstream out(dir_ / ex::kStampBlobFile, std::ios::binary | std::ios::trunc);
    out.write(b.data(), static_cast<std::streamsize>(b.size()));
  }
  // Loading must throw IoError whose message contains `needle`.
  void expectRejected(const std::string& needle) const {
    try {
      ex::loadExampleSet(dir_.string());
      FAIL() << "loaded a corrupt set (expected: " << needle << ")";
    } catch (const de::IoError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "message: " << e.what();
    }
  }

  fs::path dir_;
};

}  // namespace

TEST(ExampleValidation, Fnv1aMatchesPublishedVectors) {
  // Test vectors of the FNV specification (empty string, "a", "foobar").
  EXPECT_EQ(ex::fnv1a64("", 0), 0xcbf29ce484222325ULL);
  EXPECT_EQ(ex::fnv1a64("a", 1), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(ex::fnv1a64("foobar", 6), 0x85944171f73967e8ULL);
}

TEST_F(ExampleSetIo, RoundTripIsExact) {
  const ex::ExampleSet original = makeSet();
  const ex::ExampleSet loaded = ex::loadExampleSet(dir_.string());
  EXPECT_EQ(loaded.metadata.scene, original.metadata.scene);
  EXPECT_EQ(loaded.metadata.material, original.metadata.material);
  EXPECT_EQ(loaded.metadata.description, original.metadata.description);
  ASSERT_EQ(loaded.examples.size(), original.examples.size());
  for (std::size_t i = 0; i < original.examples.size(); ++i) {
    const ex::Example& a = original.examples[i];
    const ex::Example& b = loaded.examples[i];
    EXPECT_EQ(a.contact, b.contact);
    EXPECT_EQ(a.frame, b.frame);
    EXPECT_EQ(a.rho.values(), b.rho.values());
    EXPECT_EQ(a.mu.values(), b.mu.values());
    EXPECT_EQ(a.mu.firstOrder(), b.mu.firstOrder());
    EXPECT_EQ(a.mu.channels(), b.mu.channels());
    EXPECT_EQ(a.stampRadius, b.stampRadius);
    EXPECT_EQ(a.pattern.indentDepth, b.pattern.indentDepth);
    EXPECT_EQ(a.pattern.drag, b.pattern.drag);
    EXPECT_EQ(a.sceneId, b.sceneId);
    ASSERT_EQ(a.stamp.size(), b.stamp.size());
    EXPECT_EQ(a.stampLayers, b.stampLayers);
    EXPECT_EQ(cv::norm(a.stamp, b.stamp, cv::NORM_INF), 0.0);
  }
}

TEST_F(ExampleSetIo, VolumeStampLayersRoundTripAndMustDivideTheRows) {
  ex::ExampleSet set = makeSet();
  for (ex::Example& e : set.examples) {
    e.stamp = cv::Mat(3 * e.stamp.cols, e.stamp.cols, CV_32FC3, cv::Scalar(1e-4, -2e-4, 3e-4));
    e.stampLayers = 3;
  }
  ex::saveExampleSet(set, dir_.string());
  const ex::ExampleSet loaded = ex::loadExampleSet(dir_.string());
  for (const ex::Example& e : loaded.examples) {
    EXPECT_EQ(e.stampLayers, 3);
    EXPECT_EQ(e.stamp.rows, 3 * e.stamp.cols);
  }
  nlohmann::json m = manifest();
  m["examples"][0]["stamp_layers"] = 2;
  writeManifest(m);
  expectRejected("stamp_layers");
  for (auto& e : m["examples"]) e.erase("stamp_layers");  // sets without the field hold surface stamps: any row count
  writeManifest(m);
  EXPECT_EQ(ex::loadExampleSet(dir_.string()).examples[0].stampLayers, 1);
}

TEST_F(ExampleSetIo, TruncatedBlobIsRejected) {
  std::vector<char> b = blob();
  b.resize(b.size() - 7);
  writeBlob(b);
  expectRejected("truncated");
}

TEST_F(ExampleSetIo, FlippedByteIsRejected) {
  std::vector<char> b = blob();
  b[b.size() / 2] ^= 0x10;
  writeBlob(b);
  expectRejected("checksum mismatch");
}

TEST_F(ExampleSetIo, NanInStampIsRejectedEvenWithMatchingChecksum) {
  // A producer that wrote NaN and checksummed it: the checksum passes, the value check must not.
  std::vector<char> b = blob();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + 12 * 5, &nan, sizeof(float));
  writeBlob(b);
  nlohmann::json m = manifest();
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(ex::fnv1a64(b.data(), b.size())));
  m["stamp_blob"]["fnv1a64"] = hex;
  writeManifest(m);
  expectRejected("example 0 stamp contains NaN or Inf");
}

TEST_F(ExampleSetIo, WrongVersionIsRejected) {
  nlohmann::json m = manifest();
  m["format_version"] = 99;
  writeManifest(m);
  expectRejected("unsupported format_version 99");
}

TEST_F(ExampleSetIo, IntegersOutsideIntAreRejectedNotWrapped) {
  // get<int>() wrapped these to the valid 1 and 8: the lying manifest loaded.
  nlohmann::json m = manifest();
  m["format_version"] = 4294967297ULL;
  writeManifest(m);
  expectRejected("field manifest.format_version is outside the int range");
  m["format_version"] = ex::kExampleSetFormatVersion;
  m["examples"][0]["stamp_rows"] = 4294967304LL;
  writeManifest(m);
  expectRejected("field manifest.examples[0].stamp_rows is outside the int range");
  m["examples"][0]["stamp_rows"] = -4294967288LL;
  writeManifest(m);
  expectRejected("field manifest.examples[0].stamp_rows is outside the int range");
}

TEST_F(ExampleSetIo, MissingFieldIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][1].erase("stamp_radius");
  writeManifest(m);
  expectRejected("missing field manifest.examples[1].stamp_radius");
}

TEST_F(ExampleSetIo, NanInManifestIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][2]["contact"][1] = std::numeric_limits<double>::quiet_NaN();  // serialised as null
  writeManifest(m);
  expectRejected("manifest.examples[2].contact[1] is not a number");
}

TEST_F(ExampleSetIo, NonOrthonormalFrameIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][0]["frame_rows"][0][0] = m["examples"][0]["frame_rows"][0][0].get<double>() + 0.01;
  writeManifest(m);
  expectRejected("example 0: frame is not orthonormal");
}

TEST_F(ExampleSetIo, NonPositiveRadiusIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][0]["stamp_radius"] = 0.0;
  writeManifest(m);
  expectRejected("example 0: stamp radius is not positive");
}

TEST_F(ExampleSetIo, DescriptorSizeMismatchIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][0]["mu"]["values"].erase(0);
  writeManifest(m);
  expectRejected("manifest.examples[0].mu.values has");
}

TEST_F(ExampleSetIo, StampSizeInconsistentWithBlobIsRejected) {
  nlohmann::json m = manifest();
  m["examples"][2]["stamp_rows"] = 9;  // claims another grid than example 0
  writeManifest(m);
  expectRejected("manifest.examples[2] stamp size differs from example 0");
  m = manifest();
  for (int i = 0; i < 3; ++i) {  // a consistent 9x6 grid claims more bytes than the blob holds
    m["examples"][i]["stamp_rows"] = 9;
    m["examples"][i]["stamp_offset_bytes"] = i * 9 * 6 * 3 * 4;
  }
  writeManifest(m);
  expectRejected("past the blob");
}

TEST_F(ExampleSetIo, MixedStampRadiiAreRejected) {
  nlohmann::json m = manifest();
  m["examples"][1]["stamp_radius"] = 0.02;
  writeManifest(m);
  expectRejected("manifest.examples[1].stamp_radius differs from example 0");
}

TEST_F(ExampleSetIo, MissingManifestAndGarbageAreRejected) {
  std::ofstream(dir_ / ex::kManifestFile, std::ios::trunc) << "{ not json";
  expectRejected("not valid JSON");
  fs::remove(dir_ / ex::kManifestFile);
  expectRejected("missing manifest");
}

TEST_F(ExampleSetIo, RandomByteCorruptionNeverCrashes) {
  // Flip random bytes of the manifest: loading either succeeds (a harmless change) or throws IoError.
  const std::string original = manifest().dump(1);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::string text = original;
    for (int k = 0; k < 3; ++k) text[rng() % text.size()] = static_cast<char>(rng() % 256);
    std::ofstream(dir_ / ex::kManifestFile, std::ios::trunc) << text;
    try {
      ex::loadExampleSet(dir_.string());
    } catch (const de::IoError&) {
    }
  }
}

TEST(ExampleValidation, SaveRejectsInvalidExamples) {
  ex::ExampleSet set = makeSet();
  set.examples[1].frame(0, 0) += 0.1;
  EXPECT_THROW(ex::saveExampleSet(set, (fs::temp_directory_path() / "de_never_written").string()), de::InvalidInputError);
  set = makeSet();
  set.examples[2] = makeExample(3, 5, 5);
  EXPECT_THROW(ex::saveExampleSet(set, (fs::temp_directory_path() / "de_never_written").string()), de::InvalidInputError);
  set = makeSet();
  set.examples.clear();
  EXPECT_THROW(ex::saveExampleSet(set, (fs::temp_directory_path() / "de_never_written").string()), de::InvalidInputError);
  EXPECT_NE(ex::exampleProblem([] {
              ex::Example e = makeExample(1);
              e.frame.col(2) *= -1.0;
              return e;
            }()).find("right-handed"),
            std::string::npos);
}
