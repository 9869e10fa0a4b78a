#pragma once
// Reader of the nodal displacements that ccx prints to <job>.dat for *NODE PRINT ... U: one block per
// increment, a header " displacements (vx,vy,vz) for set NALL and time  0.1000000E+01", a blank line, then
// one line "node ux uy uz" per node of the set (Fortran E format, 7 significant digits).
#include <Eigen/Core>
#include <istream>
#include <string>

namespace deformation_enrichment::elasticity {

struct CalculixDisplacements {
  double time = 0.0;       ///< step time of the block (1 when the step completed)
  Eigen::Matrix3Xd values;  ///< 3 x nodeCount; column v is node v + 1
};

/// The last displacement block of `in`, which must list every node 1..nodeCount exactly once. Throws
/// IoError naming `source` and the line for no block, a malformed line, or a node out of range, repeated
/// or missing.
CalculixDisplacements readCalculixDisplacements(std::istream& in, Eigen::Index nodeCount, const std::string& source);

}  // namespace deformation_enrichment::elasticity
