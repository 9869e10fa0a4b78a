// readMd2 on hostile headers (fuzz_md2 findings): typed errors, no arithmetic overflow.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/md2_reader.hpp"

using namespace deformation_enrichment;

namespace {

// A 68-byte MD2 header (magic, version 8, the 15 int32 fields) followed by `padding` zero bytes.
std::string writeMd2(const std::vector<std::int32_t>& fields, std::size_t padding) {
  const std::string path = testing::TempDir() + "de_md2_header_" + std::to_string(::getpid()) + ".md2";
  std::ofstream out(path, std::ios::binary);
  out.write("IDP2", 4);
  const std::int32_t version = 8;
  out.write(reinterpret_cast<const char*>(&version), 4);
  out.write(reinterpret_cast<const char*>(fields.data()), static_cast<std::streamsize>(4 * fields.size()));
  out << std::string(padding, '\0');
  return path;
}

}  // namespace

TEST(Md2HeaderChecks, FrameSizeIsComparedWithoutOverflow) {
  // fuzz_md2: 40 + 4 * 1224736771 overflowed int and wrapped to exactly the declared frame size, so the
  // header passed as consistent and the reader went on with a 600 MB frame.
  const std::int32_t vertices = 1224736771;
  const auto wrapped = static_cast<std::int32_t>(static_cast<std::uint32_t>(40u + 4u * std::uint32_t(vertices)));
  const std::string path = writeMd2({64, 64, wrapped, 0, vertices, 0, 1, 0, 1, 68, 68, 68, 80, 80, 80}, 12);
  try {
    shape_space::readMd2(path);
    ADD_FAILURE() << "accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("frame size does not match the vertex count"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}
