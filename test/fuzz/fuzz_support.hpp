#pragma once
// Shared by the libFuzzer harnesses: invariant checks on what a loader accepted, and a scratch file in
// /dev/shm for the reader that only takes a path (MD2).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/mesh/volume_mesh_io.hpp"

// An accepted input whose result breaks the loader's contract is a finding: abort, so libFuzzer saves it.
#define DE_FUZZ_CHECK(condition)                                                            \
  do {                                                                                      \
    if (!(condition)) {                                                                     \
      std::fprintf(stderr, "%s:%d: loader contract broken: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                         \
    }                                                                                       \
  } while (false)

namespace deformation_enrichment::fuzz {

/// What every triangle mesh a reader accepts satisfies (repeated corners are allowed: OBJ/PLY keep them).
inline void checkTriangleMesh(const mesh::TriangleMesh& m) {
  DE_FUZZ_CHECK(m.numVertices() > 0 && m.numTriangles() > 0 && m.vertices.allFinite());
  DE_FUZZ_CHECK(m.triangles.minCoeff() >= 0 && m.triangles.maxCoeff() < m.numVertices());
}

/// What every volume mesh a reader accepts satisfies: positively oriented tets over finite nodes, one region
/// and one file id per tet and node.
inline void checkVolumeMesh(const mesh::VolumeMeshFile& f) {
  mesh::validate(f.mesh);  // throws InvalidInputError (not caught by the harness: a finding) when broken
  DE_FUZZ_CHECK(f.region.size() == f.mesh.numTets());
  DE_FUZZ_CHECK(static_cast<Eigen::Index>(f.nodeIds.size()) == f.mesh.numVertices());
  DE_FUZZ_CHECK(f.report.reorientedTets >= 0 && f.report.reorientedTets <= f.mesh.numTets());
}

/// The OBJ / PLY harnesses: `read(stream, name)` on the input's bytes; IoError is a rejection.
template <class Reader>
void readMeshBytes(Reader read, const std::uint8_t* data, std::size_t size, const std::string& name) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    checkTriangleMesh(read(in, name));
  } catch (const IoError&) {
  }
}

/// `/dev/shm/de_fuzz_<pid><suffix>`, rewritten with every input and removed at exit.
class ScratchFile {
public:
  explicit ScratchFile(const std::string& suffix)
      : path_("/dev/shm/de_fuzz_" + std::to_string(::getpid()) + suffix) {}
  ~ScratchFile() { std::remove(path_.c_str()); }

  const std::string& write(const std::uint8_t* data, std::size_t size) const {
    std::FILE* file = std::fopen(path_.c_str(), "wb");
    DE_FUZZ_CHECK(file != nullptr);
    DE_FUZZ_CHECK(std::fwrite(data, 1, size, file) == size);
    DE_FUZZ_CHECK(std::fclose(file) == 0);
    return path_;
  }

private:
  std::string path_;
};

}  // namespace deformation_enrichment::fuzz
