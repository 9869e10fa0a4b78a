// End-to-end run of the de_simulate tool on a small slab: it must write one OBJ surface per step and a
// JSON log whose steps converged, and fail with a clear message on a tool that misses the tissue.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {
const std::string kTool = std::string(DE_TOOL_DIR) + "/de_simulate";

int run(const std::string& arguments) { return std::system((kTool + " " + arguments + " 2>/dev/null").c_str()); }
}  // namespace

TEST(DeSimulateCli, DragWritesSurfacesAndLog) {
  ASSERT_TRUE(std::filesystem::exists(kTool)) << "de_simulate not found at " << kTool;
  const std::string out = testing::TempDir() + "de_simulate_cli_" + std::to_string(::getpid());
  std::filesystem::remove_all(out);
  ASSERT_EQ(run("--scene slab --cells 8 8 2 --mode drag --indent-steps 2 --steps 2 --depth 0.002 "
                "--drag-distance 0.004 --tool-radius 0.007 --out " + out), 0);
  for (int step = 0; step <= 4; ++step) {
    char name[32];
    std::snprintf(name, sizeof(name), "/step_%03d.obj", step);
    EXPECT_TRUE(std::filesystem::exists(out + name)) << name;
  }
  std::ifstream in(out + "/log.json");
  const nlohmann::json log = nlohmann::json::parse(in);
  ASSERT_EQ(log["steps"].size(), 4u);
  for (const auto& step : log["steps"]) {
    EXPECT_TRUE(step["converged"].get<bool>());
    EXPECT_GT(step["iterations"].get<int>(), 0);
    EXPECT_EQ(step["newton"].size(), step["iterations"].get<std::size_t>());
    for (const auto& iteration : step["newton"]) EXPECT_GE(iteration["conjugate_gradient_iterations"].get<int>(), 0);
  }
  // Last step: tool displaced 2 mm down and 4 mm along x.
  const auto displacement = log["steps"].back()["tool_displacement"];
  EXPECT_NEAR(displacement[0].get<double>(), 0.004, 1e-12);
  EXPECT_NEAR(displacement[2].get<double>(), -0.002, 1e-12);
  // A tool beside the tissue is an input error (exit code 1), not a crash.
  EXPECT_EQ(WEXITSTATUS(run("--scene slab --cells 4 4 2 --point 0.5 0.5 --out " + out)), 1);
  std::filesystem::remove_all(out);
}

// Command-line errors exit 1 like any other input error of the tools (command_line.hpp), not with CLI11's
// own codes (109 for an unknown option, 105 for a value out of range); --help exits 0.
TEST(DeSimulateCli, CommandLineErrorsExitOne) {
  ASSERT_TRUE(std::filesystem::exists(kTool)) << "de_simulate not found at " << kTool;
  EXPECT_EQ(WEXITSTATUS(run("--no-such-option")), 1);
  EXPECT_EQ(WEXITSTATUS(run("--scene slab --depth not-a-number")), 1);
  EXPECT_EQ(WEXITSTATUS(run("--help >/dev/null")), 0);
  // Solver settings out of range are refused before anything is written.
  const std::string out = testing::TempDir() + "de_simulate_bad_settings_" + std::to_string(::getpid());
  std::filesystem::remove_all(out);
  for (const char* tolerance : {"1", "-0.1", "nan"})
    EXPECT_EQ(WEXITSTATUS(run(std::string("--scene slab --cells 4 4 2 --preconditioned-tolerance ") + tolerance + " --out " + out)), 1)
        << tolerance;
  EXPECT_FALSE(std::filesystem::exists(out));
}
