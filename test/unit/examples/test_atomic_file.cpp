// A file written whole or not at all (atomic_file.hpp): the example set, plans, meshes and tool reports use it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace fs = std::filesystem;

namespace {

std::string contentsOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path freshFolder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

}  // namespace

TEST(AtomicFile, WritesAndReplacesWholeLeavingNoTemporary) {
  const fs::path folder = freshFolder("de_atomic_file_replace");
  const fs::path path = folder / "report.json";
  de::writeFileAtomically(path, "first\n");
  EXPECT_EQ(contentsOf(path), "first\n");
  const std::string binary("a\0b", 3);
  de::writeFileAtomically(path, binary);
  EXPECT_EQ(contentsOf(path), binary);
  EXPECT_FALSE(fs::exists(folder / "report.json.tmp"));
}

TEST(AtomicFile, AFailedWriteThrowsNamingThePathAndKeepsThePreviousState) {
  const fs::path folder = freshFolder("de_atomic_file_fail");
  // No such folder: nothing is created.
  const fs::path missing = folder / "no_such_folder" / "plan.csv";
  try {
    de::writeFileAtomically(missing, "x");
    FAIL() << "writing into a missing folder must throw";
  } catch (const de::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));
  // The target is a folder: the rename fails, the folder stays and the temporary file is removed.
  const fs::path occupied = folder / "occupied";
  fs::create_directories(occupied);
  EXPECT_THROW(de::writeFileAtomically(occupied, "x"), de::IoError);
  EXPECT_TRUE(fs::is_directory(occupied));
  EXPECT_FALSE(fs::exists(folder / "occupied.tmp"));
}
