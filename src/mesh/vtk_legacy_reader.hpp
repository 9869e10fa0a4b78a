#pragma once
// The legacy VTK file format's unstructured grid, read without VTK (private to src/mesh): VTK 9.1's legacy
// reader trusts the counts in a file and reads past its arrays or dereferences null on corrupt ones (found
// by fuzz_vtk), so .vtk files are parsed here, checking every count against what the file holds.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace deformation_enrichment::mesh::detail {

/// Points and cells of an unstructured grid: cell c has type types[c] and the points
/// connectivity[offsets[c] .. offsets[c + 1]).
struct VtkCells {
  Eigen::Matrix3Xd points;
  std::vector<int> types;
  std::vector<long> offsets{0};
  std::vector<long> connectivity;
};

/// A legacy .vtk file (versions 2.0-5.1, ASCII or BINARY) holding DATASET UNSTRUCTURED_GRID: its POINTS,
/// CELLS (counted or OFFSETS / CONNECTIVITY) and CELL_TYPES; point and cell data are ignored. Throws
/// IoError naming `name` and the problem. Point ids are not range-checked here.
VtkCells readVtkLegacy(const std::string& bytes, const std::string& name);

}  // namespace deformation_enrichment::mesh::detail
