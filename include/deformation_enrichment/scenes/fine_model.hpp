#pragma once
// The display surface and the fine model of a scene with mesh files (docs/scenes.md). A clean closed
// surface is used as it is and filled by a fine tet mesh that keeps its vertices (tetgen -pY); a dirty one
// (real organ files self-intersect, repeat vertices, have holes) is repaired first (mesh/surface_repair);
// where it still cannot be filled, the fine model is the coarse volume refined [Bey95] with the display
// surface embedded in it, as the coarse model embeds it.
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::scenes {

struct DisplaySurface {
  mesh::TriangleMesh surface;  ///< metres; the repaired surface when the file's needed repair
  bool fillable = false;       ///< closed and free of self-intersections: a tet mesh can conform to it
  std::string report;          ///< what the file holds, and the repair's counts when there was one
};

/// Reads the scene's surface in metres. A closed manifold surface without duplicate vertices, zero-area
/// triangles or self-intersections is kept as it is (same vertices, same order); any other is repaired,
/// or, where repair is impossible, kept as it is and marked not fillable.
/// Throws InvalidInputError / IoError for an unreadable file or a surface with no usable triangle.
DisplaySurface readDisplaySurface(const scene_file::SceneDescription& scene);

/// The fine model's largest tet volume when a scene gives none: a regular tet whose edge is the display
/// surface's median edge length, so the fine model is as fine inside as the display surface is on it.
double defaultFineMaxVolume(const mesh::TriangleMesh& surface);

struct FineModel {
  mesh::TetMesh mesh;
  std::vector<int> surfaceToFine;  ///< display vertex -> its fine node, or the fine boundary node nearest it
  std::optional<mesh::BarycentricEmbedding> surfaceOnFine;  ///< when the fine model does not keep the display vertices
  std::string report;
};

/// A fillable surface: tetgen -pqY with the scene's fine max_volume (or the default). Otherwise, or when
/// tetgen refuses it, `coarse` refined until its mean tet volume is at most that volume, with the display
/// surface embedded (vertices farther than the scene's max_outside refused). Throws InvalidInputError
/// naming why the conforming model could not be made when the fallback fails too.
FineModel buildFineModel(const scene_file::SceneDescription& scene, const DisplaySurface& display, const mesh::TetMesh& coarse);

}  // namespace deformation_enrichment::scenes
