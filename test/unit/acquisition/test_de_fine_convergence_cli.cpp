// de_fine_convergence on bad input: exit 1 with a message naming the option, nothing on stdout.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace {

const std::string kTool = std::string(DE_TOOL_DIR) + "/de_fine_convergence";

// Exit code and combined output of the tool with `arguments`.
std::pair<int, std::string> run(const std::string& arguments) {
  std::string output;
  FILE* pipe = ::popen((kTool + " " + arguments + " 2>&1").c_str(), "r");
  if (!pipe) return {-1, ""};
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe)) output += buffer;
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace

TEST(DeFineConvergenceCli, BadLevelsAndScenesExitOneWithAReason) {
  ASSERT_TRUE(std::filesystem::exists(kTool)) << "de_fine_convergence not found at " << kTool;
  for (const auto& [arguments, expect] : std::vector<std::pair<std::string, std::string>>{
           {"--scene slab --levels 1,two", "--levels: 'two' is not a factor >= 1"},
           {"--scene slab --levels 2,4", "the levels must start with 1"},
           {"--scene slab --levels 1,4,2", "the levels must be ascending"},
           {"--scene nowhere.yaml", "nowhere.yaml"}}) {
    SCOPED_TRACE(arguments);
    const auto [code, output] = run(arguments);
    EXPECT_EQ(code, 1);
    EXPECT_NE(output.find(expect), std::string::npos) << output;
    EXPECT_EQ(output.find("\"levels\""), std::string::npos) << output;  // no JSON
  }
}
