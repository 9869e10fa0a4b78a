// fuzz_make_seeds OUT_DIR SOURCE_DIR [MD2_FILE...]: writes OUT_DIR/<harness>/generated_* seeds that are
// cheaper to generate than to keep in git: an example set written by saveExampleSet, clouds and polygon
// meshes in cloud_input.hpp's format, a tiny MD2 and two-frame cuts of the given real ones, and the
// repository's TetGen box in fuzz_tetgen's format.
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cloud_input.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/point_cloud_layout.hpp"

namespace de = deformation_enrichment;
namespace ex = deformation_enrichment::examples;
namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeSeed(const fs::path& dir, const std::string& name, const std::string& bytes) {
  fs::create_directories(dir);
  std::ofstream(dir / ("generated_" + name), std::ios::binary) << bytes;
}

std::string asString(const std::vector<std::uint8_t>& bytes) { return std::string(bytes.begin(), bytes.end()); }

ex::Example example(double shift) {
  ex::Example e;
  e.contact = Eigen::Vector3d(0.01 * shift, 0.0, 0.02);
  e.frame = Eigen::AngleAxisd(0.3 * shift, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  e.rho = de::hermite::MomentList(0, 1, 1);
  e.mu = de::hermite::MomentList(1, 1, 3);
  e.rho.values().setConstant(0.5 + shift);
  e.mu.values().setConstant(1e-3 * shift);
  e.stamp = cv::Mat(2, 3, CV_32FC3, cv::Scalar(1e-4 * shift, -2e-4, 3e-4));
  e.stampRadius = 0.01;
  e.pattern.indentDepth = 0.003;
  e.pattern.drag = Eigen::Vector3d(0.001 * shift, 0.0, 0.0);
  e.sceneId = "slab";
  return e;
}

// manifest, NUL, blob (fuzz_example_set's input format).
std::string exampleSetSeed() {
  ex::ExampleSet set;
  set.metadata.scene = "slab";
  set.metadata.material = {{"young_modulus", 3000.0}};
  set.metadata.description = "fuzz seed";
  set.examples = {example(1.0), example(2.0)};
  const fs::path dir = fs::temp_directory_path() / ("de_fuzz_seed_set_" + std::to_string(::getpid()));
  ex::saveExampleSet(set, dir.string());
  const std::string seed = readFile(dir / ex::kManifestFile) + '\0' + readFile(dir / ex::kStampBlobFile);
  fs::remove_all(dir);
  return seed;
}

// width x height points of x, (rgb,) y, z float32 with `padding` bytes after every row.
de::fuzz::CloudInput cloud(std::uint32_t width, std::uint32_t height, bool rgb, std::uint32_t padding) {
  de::fuzz::CloudInput c;
  const std::uint32_t gap = rgb ? 4 : 0;
  c.layout.fields = {{"x", 0, de::mesh::kFloat32Field, 1}, {"y", 4 + gap, de::mesh::kFloat32Field, 1},
                     {"z", 8 + gap, de::mesh::kFloat32Field, 1}};
  if (rgb) c.layout.fields.push_back({"rgb", 4, de::mesh::kFloat32Field, 1});
  c.layout.width = width;
  c.layout.height = height;
  c.layout.pointStep = 12 + gap;
  c.layout.rowStep = c.layout.pointStep * width + padding;
  c.data.assign(std::size_t(c.layout.rowStep) * height, 0);
  Eigen::Matrix3Xf positions = Eigen::Matrix3Xf::Random(3, Eigen::Index(width) * height);
  de::mesh::encodePositions(positions, c.layout, c.data.data(), c.data.size());
  return c;
}

// Quake II MD2: 3 vertices, 2 triangles (the second repeats a vertex), 2 frames.
std::string md2Seed() {
  std::vector<std::uint8_t> b;
  const auto i32 = [&](std::int32_t v) { de::fuzz::detail::put(b, v); };
  const auto i16 = [&](std::int16_t v) { de::fuzz::detail::put(b, v); };
  const auto f32 = [&](float v) { de::fuzz::detail::put(b, v); };
  const int vertices = 3, triangles = 2, frames = 2, frameSize = 40 + 4 * vertices;
  const int trianglesAt = 68, framesAt = trianglesAt + 12 * triangles, end = framesAt + frames * frameSize;
  b.insert(b.end(), {'I', 'D', 'P', '2'});
  for (int v : {8, 64, 64, frameSize, 0, vertices, 0, triangles, 0, frames, 68, 68, trianglesAt, framesAt, end, end}) i32(v);
  for (std::int16_t v : {0, 1, 2, 0, 0, 0, 0, 0, 1, 0, 0, 0}) i16(v);
  for (int f = 0; f < frames; ++f) {
    for (float v : {0.1f, 0.1f, 0.1f, -1.0f, -1.0f, float(f)}) f32(v);
    char name[16] = {};
    std::snprintf(name, sizeof name, "stand%02d", f);
    b.insert(b.end(), name, name + 16);
    b.insert(b.end(), {0, 0, 0, 0, 20, 0, 0, 0, 0, 20, 0, 0});
  }
  return asString(b);
}

// A real MD2 cut to its triangles and first `frames` frames (skins, texture coordinates and GL commands
// dropped): real geometry at a size the fuzzer mutates quickly. Empty if `file` is not a readable MD2.
std::string reducedMd2(const fs::path& file, int frames) {
  if (!fs::is_regular_file(file)) return {};
  const std::string in = readFile(file);
  std::int32_t h[17];
  if (in.size() < sizeof h || in.compare(0, 4, "IDP2") != 0) return {};
  std::memcpy(h, in.data(), sizeof h);  // h[0] magic, h[1] version, then the 15 header fields
  const std::int64_t frameSize = h[4], vertices = h[6], triangles = h[8], framesAt = h[14], trianglesAt = h[13];
  frames = std::min<int>(frames, h[10]);
  if (frameSize != 40 + 4 * vertices || trianglesAt + 12 * triangles > std::int64_t(in.size()) ||
      framesAt + frames * frameSize > std::int64_t(in.size()))
    return {};
  const std::int64_t newFramesAt = 68 + 12 * triangles, end = newFramesAt + frames * frameSize;
  std::vector<std::uint8_t> b;
  b.insert(b.end(), {'I', 'D', 'P', '2'});
  for (std::int64_t v : {std::int64_t(8), std::int64_t(h[2]), std::int64_t(h[3]), frameSize, std::int64_t(0), vertices,
                         std::int64_t(0), triangles, std::int64_t(0), std::int64_t(frames), std::int64_t(68),
                         std::int64_t(68), std::int64_t(68), newFramesAt, end, end})
    de::fuzz::detail::put(b, static_cast<std::int32_t>(v));
  b.insert(b.end(), in.begin() + trianglesAt, in.begin() + trianglesAt + 12 * triangles);
  b.insert(b.end(), in.begin() + framesAt, in.begin() + framesAt + frames * frameSize);
  return asString(b);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fuzz_make_seeds OUT_DIR SOURCE_DIR [MD2_FILE...]\n");
    return 2;
  }
  const fs::path out(argv[1]), source(argv[2]);
  writeSeed(out / "fuzz_example_set", "two_examples", exampleSetSeed());
  writeSeed(out / "fuzz_point_cloud", "xyz", asString(de::fuzz::encodeCloudInput(cloud(5, 1, false, 0), false)));
  writeSeed(out / "fuzz_point_cloud", "xyzrgb_organised_padded",
            asString(de::fuzz::encodeCloudInput(cloud(3, 2, true, 8), false)));
  de::fuzz::CloudInput tetra = cloud(4, 1, false, 0);
  tetra.polygons = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  writeSeed(out / "fuzz_polygon_mesh", "tetrahedron", asString(de::fuzz::encodeCloudInput(tetra, true)));
  de::fuzz::CloudInput quad = cloud(2, 2, true, 4);
  quad.polygons = {{0, 1, 3, 2}, {0, 1}};
  writeSeed(out / "fuzz_polygon_mesh", "quad_and_line", asString(de::fuzz::encodeCloudInput(quad, true)));
  writeSeed(out / "fuzz_md2", "tiny.md2", md2Seed());
  for (int i = 3; i < argc; ++i) {
    const std::string reduced = reducedMd2(argv[i], 2);
    if (!reduced.empty()) writeSeed(out / "fuzz_md2", fs::path(argv[i]).filename().string(), reduced);
  }
  const fs::path box = source / "test/data/tetgen/box.1";
  writeSeed(out / "fuzz_tetgen", "box", readFile(box.string() + ".node") + '\0' + readFile(box.string() + ".ele"));
  return 0;
}
