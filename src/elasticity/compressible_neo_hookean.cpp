#include "deformation_enrichment/elasticity/compressible_neo_hookean.hpp"

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {
namespace {

void checkF(const Eigen::Matrix3d& F, double J) {
  if (!F.allFinite() || !(J > 0.0))
    throw InvalidInputError("CompressibleNeoHookean: F must be finite with J > 0, got J = " + std::to_string(J));
}

}  // namespace

CompressibleNeoHookean::CompressibleNeoHookean(double mu, double kappa) : mu_(mu), kappa_(kappa) {
  if (!std::isfinite(mu) || !(mu > 0.0) || !std::isfinite(kappa) || !(kappa > 0.0))
    throw InvalidInputError("CompressibleNeoHookean: mu and kappa must be finite and positive");
}

double CompressibleNeoHookean::psi(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  checkF(F, J);
  // U = C10 (I1_bar - 3) + (J - 1)^2 / D1 with I1_bar = J^(-2/3) tr(F^T F).
  return 0.5 * mu_ * (std::pow(J, -2.0 / 3.0) * F.squaredNorm() - 3.0) + 0.5 * kappa_ * (J - 1.0) * (J - 1.0);
}

Eigen::Matrix3d CompressibleNeoHookean::pk1(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  checkF(F, J);
  const Eigen::Matrix3d FinvT = F.inverse().transpose();  // dJ/dF = J F^-T
  return mu_ * std::pow(J, -2.0 / 3.0) * (F - F.squaredNorm() / 3.0 * FinvT) + kappa_ * (J - 1.0) * J * FinvT;
}

Eigen::VectorXd neoHookeanGradient(const TetFem& fem, const std::vector<CompressibleNeoHookean>& materials,
                                   const Eigen::VectorXi& materialId, const Eigen::Matrix3Xd& x) {
  if (x.cols() != fem.numVertices() || materialId.size() != fem.numTets() || materials.empty() ||
      (materialId.size() > 0 && (materialId.minCoeff() < 0 || materialId.maxCoeff() >= static_cast<int>(materials.size()))))
    throw InvalidInputError("neoHookeanGradient: positions, material ids or materials do not match the body");
  const mesh::TetMesh& rest = fem.rest();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * fem.numVertices());
  for (Eigen::Index t = 0; t < fem.numTets(); ++t) {
    const Eigen::Matrix3d P = materials[static_cast<std::size_t>(materialId[t])].pk1(fem.deformationGradient(x, t));
    // F = Ds Dm^-1 with Ds = [x1 - x0, x2 - x0, x3 - x0]: dE/dDs = V P Dm^-T gives vertices 1..3, vertex 0
    // the negative sum.
    const Eigen::Matrix3d H = fem.restVolumes()[t] * P * fem.restShapeInverse(t).transpose();
    for (int a = 1; a < 4; ++a) g.segment<3>(3 * rest.tets(a, t)) += H.col(a - 1);
    g.segment<3>(3 * rest.tets(0, t)) -= H.rowwise().sum();
  }
  return g;
}

}  // namespace deformation_enrichment::elasticity
