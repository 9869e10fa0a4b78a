#include "deformation_enrichment/mesh/tet_surface.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

TetSurface extractSurface(const TetMesh& volume) {
  if (volume.numTets() == 0) throw InvalidInputError("cannot extract the surface of a mesh without tets");
  // Faces of a positively oriented tet (v0..v3), each ordered counter-clockwise seen from outside.
  static constexpr std::array<std::array<int, 3>, 4> kFaces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
  std::map<std::array<int, 3>, std::pair<std::array<int, 3>, int>> faces;  // sorted key -> (face, count)
  for (Eigen::Index t = 0; t < volume.numTets(); ++t) {
    for (const auto& f : kFaces) {
      const std::array<int, 3> face{volume.tets(f[0], t), volume.tets(f[1], t), volume.tets(f[2], t)};
      std::array<int, 3> key = face;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.try_emplace(key, face, 0);
      ++it->second.second;
    }
  }
  TetSurface result;
  std::vector<int> volumeToSurface(volume.numVertices(), -1);
  std::vector<std::array<int, 3>> triangles;
  for (const auto& [key, entry] : faces) {
    if (entry.second != 1) continue;
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      int& mapped = volumeToSurface[entry.first[k]];
      if (mapped < 0) {
        mapped = static_cast<int>(result.surfaceToVolume.size());
        result.surfaceToVolume.push_back(entry.first[k]);
      }
      tri[k] = mapped;
    }
    triangles.push_back(tri);
  }
  result.surface.vertices.resize(3, static_cast<Eigen::Index>(result.surfaceToVolume.size()));
  for (size_t s = 0; s < result.surfaceToVolume.size(); ++s)
    result.surface.vertices.col(static_cast<Eigen::Index>(s)) = volume.vertices.col(result.surfaceToVolume[s]);
  result.surface.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (size_t t = 0; t < triangles.size(); ++t)
    result.surface.triangles.col(static_cast<Eigen::Index>(t)) << triangles[t][0], triangles[t][1], triangles[t][2];
  return result;
}

}  // namespace deformation_enrichment::mesh
