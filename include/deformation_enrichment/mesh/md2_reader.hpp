#pragma once
// Reader for Quake II MD2 animations (e.g. Debian assimp-testmodels' faerie.md2): every key frame becomes
// one TriangleMesh over the shared triangle list. Positions are stored at 8-bit precision per axis and
// frame, so consecutive frames jitter; that is what the shape-space smoothing flow is tested against.
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct Md2Animation {
  std::vector<TriangleMesh> frames;    ///< one mesh per key frame, same topology
  std::vector<std::string> frameNames;  ///< the 16-character frame names ("stand01", "run03", ...)
};

/// Reads all frames of an MD2 file. Triangles that repeat a vertex index (MD2 files contain some) are
/// dropped, as are vertices no triangle uses, so every frame passes validate(..., false).
/// Throws IoError naming the file and the problem (missing, bad magic/version, truncated, bad indices).
Md2Animation readMd2(const std::string& path);

}  // namespace deformation_enrichment::mesh
