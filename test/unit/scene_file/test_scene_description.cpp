// Scene files: the shipped scenes parse; every bad key, type, range and file is refused with a message that
// names the file, the line and the key; the provenance form reads back as the same scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

using namespace deformation_enrichment;
using scene_file::readSceneFile;

namespace {

struct SceneDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("de_scene_" + std::to_string(::getpid()));
  SceneDir() {
    std::filesystem::create_directories(path);
    std::ofstream(path / "organ.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::ofstream(path / "plan.csv") << "0,0,0,0.001,0,0,0\n";
  }
  ~SceneDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& text) const {
    const std::string file = (path / "scene.yaml").string();
    std::ofstream(file) << text;
    return file;
  }
};

const char* kGood = R"(name: organ
units: 0.01
surface: organ.obj
coarse: {max_volume: 2.0e-6}
fine: {max_volume: 1.0e-7}
material: {young: 5000, poisson: 0.45}
skin: {thickness: 0.0008, young: 200000, poisson: 0.3}
fixed: {box: [0, 0, 0, 1, 1, 0.1]}
tool: {radius: 0.004, stiffness: 1.0e9}
stamp: {radius: 0.02, resolution: 24}
plan: plan.csv
)";

// The message of the error `text` raises, which must be of type E.
template <class E>
std::string errorOf(const SceneDir& dir, const std::string& text) {
  try {
    readSceneFile(dir.write(text));
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST(SceneDescription, ShippedScenesParse) {
  const auto names = scene_file::shippedScenes();
  for (const char* name : {"slab", "pillow", "meniscus"}) {
    SCOPED_TRACE(name);
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end());
    const scene_file::SceneDescription d = readSceneFile(scene_file::findSceneFile(name));
    EXPECT_EQ(d.name, name);
    EXPECT_TRUE(d.procedural);
  }
  const scene_file::SceneDescription slab = readSceneFile(scene_file::findSceneFile("slab"));
  EXPECT_EQ(slab.stamp.radius, 0.03);
  EXPECT_EQ(slab.descriptors.windowScale, 0.006);
  EXPECT_NE(slab.plan.find("slab_plan.csv"), std::string::npos);
  EXPECT_THROW(scene_file::findSceneFile("no_such_scene"), IoError);
}

TEST(SceneDescription, AUsersSceneReadsWithUnitsAndRelativePaths) {
  const SceneDir dir;
  const scene_file::SceneDescription d = readSceneFile(dir.write(kGood));
  EXPECT_EQ(d.name, "organ");
  EXPECT_EQ(d.surface, (dir.path / "organ.obj").string());
  EXPECT_TRUE(d.volume.empty());
  EXPECT_EQ(d.material.young, 5000.0);
  ASSERT_TRUE(d.skin);
  EXPECT_EQ(d.skin->thickness, 0.0008);
  ASSERT_TRUE(d.fixed);
  EXPECT_EQ(d.fixed->kind, scene_file::FixedRegion::Kind::Box);
  EXPECT_DOUBLE_EQ(d.fixed->boxHi.z(), 0.001);  // 0.1 file units of 1 cm
  EXPECT_EQ(d.stamp.resolution, 24);
  EXPECT_EQ(d.plan, (dir.path / "plan.csv").string());
  // The provenance form (every key explicit, files by name) reads back as the same scene.
  const scene_file::SceneDescription back = scene_file::parseSceneText(scene_file::sceneYaml(d), "provenance");
  EXPECT_EQ(scene_file::sceneYaml(back), scene_file::sceneYaml(d));
  EXPECT_EQ(back.surface, "organ.obj");
  EXPECT_EQ(back.fixed->boxHi, d.fixed->boxHi);
}

TEST(SceneDescription, BadKeysTypesRangesAndFilesAreNamed) {
  const SceneDir dir;
  struct Case {
    std::string from, to, expect;
  };
  const std::vector<Case> invalid = {
      {"units: 0.01", "units: 0", "'units' must be positive"},
      {"units: 0.01", "units: -2", "'units' must be positive"},
      {"units: 0.01", "unit: 0.01", "'unit' is not a known key"},
      {"poisson: 0.45}", "poisson: 0.5}", "'material.poisson' must lie in (-1, 0.5)"},
      {"young: 5000,", "young: soft,", "'material.young' must be a finite number"},
      {"young: 5000,", "young: -5,", "'material.young' must be positive"},
      {"max_volume: 2.0e-6", "max_volume: -2.0e-6", "'coarse.max_volume' must be positive"},
      {"radius: 0.02", "radius: [1, 2]", "'stamp.radius' must be a finite number"},
      {"resolution: 24", "resolution: 1", "'stamp.resolution' must be at least 2"},
      {"box: [0, 0, 0, 1, 1, 0.1]", "box: [0, 0, 0, 1, 1]", "'fixed.box' must be a list of 6 numbers"},
      {"box: [0, 0, 0, 1, 1, 0.1]", "box: [0, 0, 1, 1, 1, 0.1]", "needs x0 < x1"},
      {"fixed: {box: [0, 0, 0, 1, 1, 0.1]}", "fixed: {vertices: [1, -2]}", "'fixed.vertices' must hold ids >= 0"},
      {"fixed: {box: [0, 0, 0, 1, 1, 0.1]}", "fixed: {}", "needs exactly one of 'vertices', 'box', 'below'"},
      {"fixed: {box: [0, 0, 0, 1, 1, 0.1]}\n", "", "needs 'fixed'"},
      {"tool: {radius: 0.004,", "tool: {model: magnet, radius: 0.004,", "'tool.model' must be penalty or dirichlet"},
      {"fine: {max_volume: 1.0e-7}\n", "", "needs 'fine: {max_volume: ...}'"},
  };
  for (const Case& c : invalid) {
    SCOPED_TRACE(c.to);
    const std::string message = errorOf<InvalidInputError>(dir, replaced(kGood, c.from, c.to));
    EXPECT_NE(message.find(c.expect), std::string::npos) << message;
    EXPECT_NE(message.find("scene.yaml:"), std::string::npos) << message;  // file and line
  }
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"organ.obj", "missing.obj"},
                                                                                  {"plan.csv", "nowhere.csv"}}) {
    const std::string message = errorOf<IoError>(dir, replaced(kGood, from, to));
    EXPECT_NE(message.find(to), std::string::npos) << message;
  }
  EXPECT_NE(errorOf<IoError>(dir, "name: [unclosed\n").find("not a valid YAML scene"), std::string::npos);
  EXPECT_THROW(readSceneFile((dir.path / "absent.yaml").string()), IoError);
}
