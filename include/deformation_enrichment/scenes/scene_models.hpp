#pragma once
// The coarse and fine simulation models of one scene file, and the display surface on the fine model
// (docs/design.md §6). Procedural scenes build both as layered grids of one shape; a scene with mesh files
// uses the user's coarse tet mesh (or tetrahedralises a simplified surface) and a fine tet mesh conforming
// to the (repaired) display surface (tetgen -pY keeps its vertices), so that fine - coarse lives on the
// display surface; a surface that cannot be repaired is embedded in the refined coarse volume instead.
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"

namespace deformation_enrichment::scenes {

struct SceneModels {
  std::string name;
  Scene coarse;  ///< material ids kBulkMaterial / kSkinMaterial, fixed and touchable (top) vertices
  Scene fine;
  mesh::TriangleMesh surface;     ///< the display surface (m), repaired when its file needed it
  std::vector<int> surfaceToFine; ///< display vertex -> its fine node (or the fine boundary node nearest it)
  /// The display surface in the fine model when the fine model does not keep its vertices (a surface that
  /// could not be made fillable: the refined coarse volume, scenes/fine_model.hpp); none: surfaceToFine is exact.
  std::optional<mesh::BarycentricEmbedding> surfaceOnFine;
  double fineEdge = 0.0;          ///< longest display-surface edge (m)
  std::string report;             ///< what was read or made (counts, reoriented / skipped cells, seconds)
};

/// Builds both models. Throws InvalidInputError / IoError naming the file or key for unreadable meshes, a
/// surface tetgen cannot tetrahedralise, a fixed region with fewer than 3 non-collinear nodes in either
/// model, or fixed node ids beyond the volume.
SceneModels buildSceneModels(const scene_file::SceneDescription& scene);

/// What the run time needs of a scene (the enrichment node's ~scene): the display surface and the coarse
/// volume around it (metres), without the fine model.
struct SceneGeometry {
  mesh::TriangleMesh surface;          ///< as buildSceneModels' display surface; may be open
  std::optional<mesh::TetMesh> volume; ///< the coarse volume (procedural: the coarse grid); none: the scene has no file
  std::string report;                  ///< what was read (counts, open or closed)
};

/// Reads (or, for a procedural scene, makes) the scene's display surface and coarse volume. Unlike
/// buildSceneModels the surface may be open and nothing is tetrahedralised. Throws InvalidInputError /
/// IoError naming the file for unreadable or invalid meshes.
SceneGeometry sceneGeometry(const scene_file::SceneDescription& scene);

}  // namespace deformation_enrichment::scenes
