// MD2 reading ([assimp-testmodels]): every frame over one topology, and bad files as IoError.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/md2_reader.hpp"

namespace de = deformation_enrichment;

namespace {
const char* kFaerie = "/usr/share/assimp/models/MD2/faerie.md2";
}

TEST(Md2Reader, ReadsAllFaerieFramesOverOneTopology) {
  const de::mesh::Md2Animation anim = de::mesh::readMd2(kFaerie);
  ASSERT_EQ(anim.frames.size(), 198u);  // the header's frame count
  ASSERT_EQ(anim.frameNames.size(), 198u);
  EXPECT_FALSE(anim.frameNames.front().empty());
  for (const auto& f : anim.frames) {
    ASSERT_EQ(f.numVertices(), anim.frames.front().numVertices());
    EXPECT_TRUE(f.triangles == anim.frames.front().triangles);
    EXPECT_NO_THROW(de::mesh::validate(f, false));
  }
  EXPECT_GT(anim.frames.front().numVertices(), 300);
  EXPECT_LE(anim.frames.front().numVertices(), 366);
  // Consecutive frames move, but far less than the model's size.
  const double size = (anim.frames[0].vertices.rowwise().maxCoeff() - anim.frames[0].vertices.rowwise().minCoeff()).norm();
  const double step = (anim.frames[1].vertices - anim.frames[0].vertices).colwise().norm().maxCoeff();
  EXPECT_GT(step, 0.0);
  EXPECT_LT(step, 0.5 * size);
}

TEST(Md2Reader, BadFilesAreIoErrors) {
  EXPECT_THROW(de::mesh::readMd2("/nonexistent/model.md2"), de::IoError);
  const std::string path = ::testing::TempDir() + "/truncated.md2";
  {
    std::ifstream in(kFaerie, std::ios::binary);
    std::vector<char> bytes(20000);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  }
  EXPECT_THROW(de::mesh::readMd2(path), de::IoError);
  {
    std::ofstream out(path, std::ios::binary);
    out << "NOTANMD2FILE-------------------------------------------------------------------------";
  }
  EXPECT_THROW(de::mesh::readMd2(path), de::IoError);
  std::remove(path.c_str());
}

