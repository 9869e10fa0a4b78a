#pragma once
// DiscreteShells' per-shape element data (squared edge lengths, areas, edge lengths, dihedral angles, hinge
// weights, and their derivatives) and eq. 4's segment terms W(a, b) + W(b, a) from two shapes' data
// (discrete_shells_path.cpp). Private to the module: pathSegments, and the reference data that
// weightedReferences and pathEnergy(data) read (discrete_shells_average.cpp).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/discrete_shells.hpp"

namespace deformation_enrichment::shape_space::detail {

class ShellPathTerms {
public:
  struct Face {
    std::array<double, 3> q;  // squared edge lengths, edge m opposite corner m
    double area, logAreaSquared;
  };
  struct FaceDerivatives {
    std::array<Eigen::Vector3d, 3> edges;  // e_m = x_m+1 - x_m+2: dq_m/dx_m+1 = 2 e_m = -dq_m/dx_m+2
    Eigen::Vector3d halfNormal;            // n / (2 |n|): dA/dx_c = halfNormal x (-e_c)
  };
  struct Edge {
    double length;
    Eigen::Vector3d direction;  // (x_0 - x_1) / length = dl/dx_0 = -dl/dx_1
  };
  struct Hinge {
    double theta, weight;  // weight: c |e|^2 / (A_1 + A_2), without the bending weight
  };
  struct HingeDerivatives {
    Eigen::Matrix<double, 12, 1> theta, weight;
  };
  struct Shape {
    std::vector<Face> faces;
    std::vector<FaceDerivatives> faceDerivatives;  // with gradients only
    std::vector<Edge> edges;                       // classic membrane only
    std::vector<Hinge> hinges;                     // with bending only
    std::vector<HingeDerivatives> hingeDerivatives;
  };

  explicit ShellPathTerms(const DiscreteShells& shells) : shells_(shells) {}

  static constexpr int kReferenceShape = -1;  // prepare's pathIndex for a shape outside a path
  // The element data of x, with derivatives if asked; throws InvalidInputError for a wrong size, non-finite
  // or degenerate shape, naming it "shape <pathIndex> of the path" or (kReferenceShape) "a reference shape".
  void prepare(const Eigen::VectorXd& x, int pathIndex, bool derivatives, Shape& out) const;
  // W(a, b) + W(b, a); adds its derivatives in a to ga and in b to gb where those are not null (the shape's
  // data then has derivatives).
  double segment(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const;

private:
  bool classic() const { return shells_.parameters_.membrane == MembraneModel::DiscreteShells; }
  bool bending() const { return shells_.parameters_.bendingWeight > 0.0; }
  double faceTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const;
  double edgeTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const;
  double hingeTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const;
  // Adds sum_m dq[m] dq_m/dx + dArea dA/dx of face t to g.
  void addFaceGradient(Eigen::Index t, const FaceDerivatives& face, const std::array<double, 3>& dq, double dArea,
                       Eigen::VectorXd& g) const;

  const DiscreteShells& shells_;
};


// DiscreteShells::referenceData: a reference shape's element data without derivatives.
struct ShellReference final : ReferenceData {
  MembraneModel membrane = MembraneModel::Hyperelastic;
  ShellPathTerms::Shape elements;
};

// data as ShellReference made by `shells` (same mesh and membrane, hinges where it bends), else null.
const ShellReference* shellReferenceOf(const ReferenceData* data, const DiscreteShells& shells);

}  // namespace deformation_enrichment::shape_space::detail
