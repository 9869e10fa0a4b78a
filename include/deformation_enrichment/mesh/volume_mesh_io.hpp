#pragma once
// Tetrahedral volume meshes from files: TetGen .node/.ele, gmsh .msh (2.2 and 4.1, ASCII and binary) and
// VTK unstructured grids (legacy .vtk, XML .vtu). Every reader keeps the nodes in file order (0-based
// index = position in the file; the file's own ids are kept in nodeIds), keeps the tetrahedra (corners
// of higher-order tets), skips other cells with a count per type, and reorders the corners of inverted
// tets so that all are positively oriented. Errors are IoErrors naming the file and the line, element
// or cell.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

struct VolumeMeshReport {
  int reorientedTets = 0;                   ///< tets read with negative orientation (corners 2, 3 swapped)
  std::map<std::string, long> skippedCells;  ///< non-tet cells by type name ("triangle", "hexahedron", ...)
  Eigen::Index unusedNodes = 0;             ///< nodes no tet references (kept: ids stay in file order)
};

struct VolumeMeshFile {
  TetMesh mesh;              ///< positively oriented tets over all nodes of the file, in file order
  Eigen::VectorXi region;    ///< per tet: gmsh physical tag, TetGen region attribute, 0 when none
  std::vector<long> nodeIds; ///< per node: its id in the file (gmsh node tag, TetGen index, VTK point index)
  VolumeMeshReport report;
};

enum class VolumeFormat { TetGen, Gmsh, VtkLegacy, VtkXml };

/// The format of `path` by its extension (.node or .ele, .msh, .vtk, .vtu; case-insensitive); throws
/// IoError for any other.
VolumeFormat volumeFormatOf(const std::string& path);

/// Reads a volume mesh chosen by extension; for TetGen `path` may name the .node or the .ele file (the
/// other is read from beside it).
VolumeMeshFile readVolumeMesh(const std::string& path);

/// One line for logs, e.g. "1200 nodes, 5000 tets, 12 reoriented, skipped 400 triangle".
std::string describe(const VolumeMeshFile& file);

}  // namespace deformation_enrichment::mesh
