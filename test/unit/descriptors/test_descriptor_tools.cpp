#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "descriptor_test_support.hpp"
#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/descriptors/site_segmentation.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;

namespace {
std::string tool(const std::string& name) { return std::string(DE_TOOL_DIR) + "/" + name; }

std::string run(const std::string& command, int* status) {
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[65536];
  while (pipe != nullptr && fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int code = pipe != nullptr ? pclose(pipe) : -1;
  *status = WIFEXITED(code) ? WEXITSTATUS(code) : -1;
  return output;
}

struct TempDir {
  std::string path;
  TempDir() {
    char pattern[] = "/tmp/de_descriptors_tools_XXXXXX";
    path = mkdtemp(pattern);
  }
  ~TempDir() { std::system(("rm -rf " + path).c_str()); }
};
}  // namespace

TEST(DescriptorTools, DeDescriptorsJsonMatchesTheLibrary) {
  ASSERT_EQ(access(tool("de_descriptors").c_str(), X_OK), 0) << "de_descriptors not found at " << tool("de_descriptors");
  TempDir dir;
  const mesh::TetMesh cube = de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 6);
  mesh::writeTetGen(dir.path + "/cube", cube);
  mesh::TetMesh deformed = cube;
  for (Eigen::Index v = 0; v < cube.numVertices(); ++v)
    deformed.vertices(0, v) += 0.03 * std::exp(-cube.vertices.col(v).squaredNorm());
  mesh::writeTetGen(dir.path + "/pushed", deformed);
  std::ofstream(dir.path + "/points.csv") << "0.7,0.31,1\n# comment\n-1, 0.2, 0.4\n";

  int status = 0;
  const std::string output =
      run(tool("de_descriptors") + " --mesh " + dir.path + "/cube.node --points " + dir.path +
              "/points.csv --order 3 --scale 0.3 --quadrature average --cutoff 3.5 --deformed " + dir.path +
              "/pushed.node --json",
          &status);
  ASSERT_EQ(status, 0) << output;
  const nlohmann::json json = nlohmann::json::parse(output);
  ASSERT_EQ(json["points"].size(), 2u);

  DescriptorOptions options;
  options.window.scale = 0.3;
  options.window.cutoff = 3.5;
  options.window.quadrature = Quadrature::Average;
  const DescriptorEvaluator evaluator(cube, options);
  const Eigen::Vector3d p(0.7, 0.31, 1.0);
  const ContactDescriptor expected = evaluator.evaluate(p, deformed.vertices);
  const auto& first = json["points"][0];
  for (int n = 0; n <= 3; ++n) {
    const auto& order = first["site"][std::to_string(n)];
    ASSERT_EQ(static_cast<int>(order.size()), hermite::numComponents(n));
    for (int c = 0; c < hermite::numComponents(n); ++c)
      EXPECT_DOUBLE_EQ(order[c].get<double>(), expected.rhoWorld.order(n)[c]);
  }
  for (int k = 0; k < 9; ++k) {
    EXPECT_DOUBLE_EQ(first["frame"][k].get<double>(), expected.frame.B(k % 3, k / 3)) << "column-major";
    EXPECT_DOUBLE_EQ(first["deformation"]["F"][k].get<double>(), expected.deformation->F(k % 3, k / 3));
  }
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 6; ++k)
      EXPECT_DOUBLE_EQ(first["deformation"]["mu"]["2"][c][k].get<double>(), expected.deformation->mu.order(2, c)[k]);

  // Bad input: a missing file gives a non-zero exit and a message, no JSON.
  run(tool("de_descriptors") + " --mesh " + dir.path + "/missing.node --points " + dir.path +
          "/points.csv --scale 0.3 --json 2>/dev/null",
      &status);
  EXPECT_EQ(status, 2);
}

TEST(DescriptorTools, DeSegmentWritesOneLabelPerSurfaceVertex) {
  ASSERT_EQ(access(tool("de_segment").c_str(), X_OK), 0) << "de_segment not found at " << tool("de_segment");
  TempDir dir;
  const mesh::TetMesh cube = de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 5);
  mesh::writeTetGen(dir.path + "/cube", cube);
  int status = 0;
  const std::string output =
      run(tool("de_segment") + " --mesh " + dir.path + "/cube.node --scale 0.2 --clusters 4", &status);
  ASSERT_EQ(status, 0) << output;
  const nlohmann::json json = nlohmann::json::parse(output);
  DescriptorOptions options;
  options.window.scale = 0.2;
  KMeansOptions kmeans;
  kmeans.clusters = 4;
  const SiteSegmentation expected = segmentSites(DescriptorEvaluator(cube, options), kmeans);
  EXPECT_EQ(json["labels"].get<std::vector<int>>(), expected.clusters.labels);
  EXPECT_EQ(json["surface_to_volume"].get<std::vector<int>>(), expected.surfaceToSample);
}
