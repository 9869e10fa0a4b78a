#pragma once
// TetGen `.node` / `.ele` files (the format of the `tetgen` command-line tool): read with validation and
// write. The region attribute of `.ele` (first tet attribute, written by `tetgen -A`) carries material ids.
#include <Eigen/Core>
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

struct TetGenMesh {
  TetMesh mesh;            ///< positively oriented tets (see readTetGen)
  Eigen::VectorXi region;  ///< per-tet region id (first tet attribute, rounded), 0 when the file has none
  int reorientedTets = 0;  ///< how many tets were read with negative orientation and flipped
  Eigen::Index unusedNodes = 0;  ///< points no tet references
  int indexBase = 0;       ///< the number of the first point in the files (0 or 1)
};

/// Reads `<base>.node` and `<base>.ele`. Index base (0 or 1) follows the first point's index, as TetGen
/// does. Comments (#) and blank lines are skipped; 10-node tets keep their four corners. Tets with
/// negative volume are reoriented (TetGen 1.5 writes positive ones, as test/data/tetgen shows, but
/// other versions and exporters differ); zero-volume tets, missing or non-numeric fields, non-finite coordinates, duplicate or
/// out-of-range indices throw IoError naming the file and line.
TetGenMesh readTetGen(const std::string& base);
/// The same from two streams holding the .node and .ele text; `base` names the files in error messages.
TetGenMesh readTetGen(std::istream& node, std::istream& ele, const std::string& base);

/// The same from two streams (the path version calls this); `base` names them in errors.
TetGenMesh readTetGen(std::istream& node, std::istream& ele, const std::string& base);

/// Writes `<base>.node` and `<base>.ele` (0-based indices). When `region` is non-empty it must hold one
/// id per tet and is written as the single tet attribute. Throws IoError if a file cannot be written and
/// InvalidInputError if region has the wrong size.
void writeTetGen(const std::string& base, const TetMesh& mesh, const Eigen::VectorXi& region = Eigen::VectorXi());

}  // namespace deformation_enrichment::mesh
