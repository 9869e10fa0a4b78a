#pragma once
// Regular refinement of a tet mesh [Bey95]: every tet split into eight at its edge midpoints (four corner
// tets and the inner octahedron cut along its shortest diagonal), so the refined mesh fills exactly the
// same volume and stays conforming. It gives a fine model of a scene whose display surface cannot be
// tetrahedralised (docs/scenes.md): the coarse volume refined, the display surface embedded in it.
#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

/// `levels` rounds of the 1:8 split (0: a copy). Vertices 0..V-1 keep their positions and order; each edge
/// midpoint is one new vertex shared by the tets around it; every child is positively oriented. Throws
/// InvalidInputError for an invalid or degenerate mesh or negative `levels`.
TetMesh refineTets(const TetMesh& mesh, int levels = 1);

/// The number of 1:8 rounds after which the mean tet volume is at most `maxVolume` (0 rounds when it is
/// already; throws InvalidInputError for a non-positive `maxVolume`).
int refinementLevels(const TetMesh& mesh, double maxVolume);

}  // namespace deformation_enrichment::mesh
