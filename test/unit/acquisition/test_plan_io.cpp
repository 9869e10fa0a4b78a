#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/error.hpp"
#include "../expect_error.hpp"

using namespace deformation_enrichment;

namespace {

std::string tempPath(const std::string& name) { return "/tmp/de_plan_" + std::to_string(::getpid()) + "_" + name; }

std::vector<acquisition::PlanEntry> parse(const std::string& text) {
  std::istringstream in(text);
  return acquisition::readPlan(in, "plan.csv");
}

void expectRejected(const std::string& text, const std::string& fragment) {
  expectErrorContaining<IoError>([&] { parse(text); }, fragment);
}

}  // namespace

TEST(PlanIo, RoundTripThroughAFile) {
  // The shipped slab plan (ten lines with drags, depths and a z) survives a write and a read.
  const auto plan = acquisition::readPlan(std::string(DE_SOURCE_DIR) + "/config/scenes/slab_plan.csv");
  ASSERT_EQ(plan.size(), 10u);
  const std::string path = tempPath("plan.csv");
  acquisition::writePlan(path, plan);
  const auto read = acquisition::readPlan(path);
  ASSERT_EQ(read.size(), plan.size());
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(read[i].point, plan[i].point);
    EXPECT_EQ(read[i].depth, plan[i].depth);
    EXPECT_EQ(read[i].drag, plan[i].drag);
  }
  std::remove(path.c_str());
  EXPECT_THROW(acquisition::readPlan("/nonexistent/plan.csv"), IoError);
}

TEST(PlanIo, CommentsBlanksAndSpacesAroundFieldsAreSkipped) {
  const auto plan = parse("# c\n\n 0, 0 ,0.02,0.003,0.001,0,0 \n\t# indented comment\n");
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0].point, Eigen::Vector3d(0, 0, 0.02));
  EXPECT_EQ(plan[0].depth, 0.003);
  EXPECT_EQ(plan[0].drag, Eigen::Vector3d(0.001, 0, 0));
}

TEST(PlanIo, BadLinesNameTheFileLineAndProblem) {
  expectRejected("0,0,0.02,0.003,0,0\n", "plan.csv:1: expected 7 fields");
  expectRejected("# x\n0,0,0.02,x,0,0,0\n", "plan.csv:2: 'x' is not a number");
  expectRejected("0,0,0.02,0.003x,0,0,0\n", "'0.003x' is not a number");  // stod would read 0.003
  expectRejected("0,0,0.02,,0,0,0\n", "'' is not a number");
  expectRejected("0,0,0.02,nan,0,0,0\n", "non-finite");
  expectRejected("0,0,0.02,1e999,0,0,0\n", "'1e999' is not a number");
  expectRejected("0,0,0.02,-0.001,0,0,0\n", "negative indentation depth");
  expectRejected("# nothing\n\n", "no interaction");
}
