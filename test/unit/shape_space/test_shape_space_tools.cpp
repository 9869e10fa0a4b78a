// The de_smooth / de_geodesic command-line tools end to end: OBJ in, OBJ out, one JSON object on stdout.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"
#include "../missing_input.hpp"
#include "flow_test_sequences.hpp"

namespace fs = std::filesystem;
namespace ss = deformation_enrichment::shape_space;
using namespace ss::test;

namespace {

std::string run(const std::string& command, int* status) {
  std::string out;
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  while (fgets(buffer, sizeof(buffer), pipe)) out += buffer;
  *status = pclose(pipe);
  return out;
}

std::string tool(const char* name) { return (fs::path(DE_TOOL_DIR) / name).string(); }

}  // namespace

TEST(ShapeSpaceTools, SmoothAndGeodesicWriteMeshesAndJson) {
  ASSERT_TRUE(fs::exists(tool("de_smooth")) && fs::exists(tool("de_geodesic"))) << "tools not found in " << DE_TOOL_DIR;
  const fs::path dir = fs::path(::testing::TempDir()) / "de_shape_space_tools";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const FlatMesh base = bumpyGrid(5, 41);
  const auto shapes = noisyBending(base, 5, 0.2, 2.0, 0.01, 9);
  std::string inputs;
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::string path = (dir / ("frame" + std::to_string(i) + ".obj")).string();
    deformation_enrichment::mesh::writeTriangleMesh(path, {ss::unflatten(shapes[i]), base.triangles});
    inputs += " " + path;
  }
  int status = 0;
  const std::string smoothJson = run(tool("de_smooth") + " --input" + inputs + " --output " + (dir / "smooth").string() +
                                         " --iterations 2 --tau 0.5 --restoring 0 --full --json", &status);
  ASSERT_EQ(status, 0) << smoothJson;
  const auto smooth = nlohmann::json::parse(smoothJson);
  ASSERT_EQ(smooth["path_energy"].size(), 3u);
  EXPECT_EQ(smooth["status"], "converged");
  EXPECT_EQ(smooth["accepted_steps"].get<int>(), 2);
  EXPECT_LT(smooth["path_energy"][2].get<double>(), smooth["path_energy"][0].get<double>());
  EXPECT_GT(smooth["seconds"].get<double>(), 0.0);
  for (size_t i = 0; i < shapes.size(); ++i) EXPECT_TRUE(fs::exists(dir / "smooth" / ("frame" + std::to_string(i) + ".obj")));
  EXPECT_EQ(smooth["subspace_dimension"].get<int>(), 0);  // full space

  // Reduced (the default): every direction of the 5 shapes (4, below the default cap of 64), or as asked.
  for (const auto& [option, dimension] : {std::pair<std::string, int>{"", 4}, {" --subspace 2", 2}}) {
    const std::string reducedJson = run(tool("de_smooth") + " --input" + inputs + " --output " + (dir / "reduced").string() +
                                            " --iterations 1 --json" + option, &status);
    ASSERT_EQ(status, 0) << reducedJson;
    EXPECT_EQ(nlohmann::json::parse(reducedJson)["subspace_dimension"].get<int>(), dimension) << option;
  }

  const std::string geoJson = run(tool("de_geodesic") + " " + (dir / "frame0.obj").string() + " " +
                                      (dir / "frame4.obj").string() + " --shapes 4 --full --json --output " +
                                      (dir / "geo").string(), &status);
  ASSERT_EQ(status, 0) << geoJson;
  const auto geo = nlohmann::json::parse(geoJson);
  EXPECT_GT(geo["length"].get<double>(), 0.0);
  EXPECT_GT(geo["path_energy"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(dir / "geo" / "geodesic_003.obj"));

  // Copies of one shape: eq. 4 = 0, nothing to smooth, no step is accepted: exit status 3, the input written.
  // (Full space: in reduced mode copies span no subspace, an error. Rigidly moved copies written to OBJ are
  // not exact copies after float rounding, so the flow would smooth that rounding.)
  std::string copies;
  for (int i = 0; i < 3; ++i) copies += " " + (dir / "frame0.obj").string();
  const std::string stalled = run(tool("de_smooth") + " --input" + copies + " --output " + (dir / "stalled").string() +
                                      " --iterations 2 --full --json", &status);
  EXPECT_EQ(WEXITSTATUS(status), 3) << stalled;
  EXPECT_EQ(nlohmann::json::parse(stalled)["status"], "nothing_accepted");
  EXPECT_TRUE(fs::exists(dir / "stalled" / "frame0.obj"));

  // Bad input: two shapes are not a sequence; the tool fails with a non-zero status and no JSON.
  const std::string bad = run(tool("de_smooth") + " --input " + (dir / "frame0.obj").string() + " " +
                                  (dir / "frame1.obj").string() + " --output " + (dir / "bad").string() + " --json", &status);
  EXPECT_NE(status, 0);
  EXPECT_TRUE(bad.empty());
  fs::remove_all(dir);
}

// An MD2 animation straight in (Debian assimp-testmodels): a frame range, one OBJ per frame named by its
// index and MD2 name, and a clear refusal of ranges the clip does not have.
TEST(ShapeSpaceTools, SmoothReadsAnMd2ClipsFrames) {
  const std::string clip = "/usr/share/assimp/models/MD2/faerie.md2";
  if (!fs::exists(clip)) DE_MISSING_INPUT("assimp-testmodels is not installed");
  const fs::path dir = fs::path(::testing::TempDir()) / "de_smooth_md2";
  fs::remove_all(dir);
  int status = 0;
  const std::string json = run(tool("de_smooth") + " --input " + clip + " --frames 0:6 --iterations 2 --output " + dir.string() + " --json", &status);
  ASSERT_EQ(status, 0) << json;
  const nlohmann::json out = nlohmann::json::parse(json);
  EXPECT_EQ(out["shapes"], 6);
  EXPECT_EQ(out["accepted_steps"], 2);
  EXPECT_LT(out["path_energy"].back().get<double>(), out["path_energy"].front().get<double>());
  std::size_t written = 0;
  for (const auto& entry : fs::directory_iterator(dir)) written += entry.path().extension() == ".obj";
  EXPECT_EQ(written, 6u);
  EXPECT_TRUE(fs::exists(dir / "000_stand01.obj"));
  for (const char* frames : {"6:2", "0:100000", "a:b", "3"}) {
    SCOPED_TRACE(frames);
    EXPECT_TRUE(run(tool("de_smooth") + " --input " + clip + " --frames " + frames + " --output " + (dir / "bad").string() + " --json", &status).empty());
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_FALSE(fs::exists(dir / "bad"));
  }
  fs::remove_all(dir);
}
