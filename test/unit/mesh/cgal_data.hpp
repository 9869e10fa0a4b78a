#pragma once
// CGAL's demo data (Debian libcgal-demo, [CGAL-data] in docs/references.md), extracted once per test
// process into a temporary folder that is removed at exit: meshes nobody here made.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "../missing_input.hpp"

namespace deformation_enrichment::test {

class CgalData {
public:
  /// The folder (with a trailing /) holding data/meshes and data/images/liver.inr.gz, or "" when
  /// libcgal-demo is missing.
  static const std::string& dir() {
    static const CgalData data;
    return data.dir_;
  }

private:
  CgalData() {
    const std::string archive = "/usr/share/doc/libcgal-demo/data.tar.gz";
    if (!std::ifstream(archive).good()) return;
    target_ = ::testing::TempDir() + "de_cgal_data_" + std::to_string(::getpid());
    std::filesystem::create_directories(target_);
    const std::string command = "tar xzf " + archive + " -C '" + target_ + "' data/meshes data/images/liver.inr.gz";
    if (std::system(command.c_str()) == 0) dir_ = target_ + "/";
  }
  ~CgalData() {
    std::error_code ignored;  // a leftover temporary folder is no reason to fail a test
    if (!target_.empty()) std::filesystem::remove_all(target_, ignored);
  }
  std::string target_, dir_;
};

}  // namespace deformation_enrichment::test

#define DE_REQUIRE_CGAL_DATA()                                   \
  if (::deformation_enrichment::test::CgalData::dir().empty()) \
  DE_MISSING_INPUT("libcgal-demo's data.tar.gz is not installed")
