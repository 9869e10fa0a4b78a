#include "deformation_enrichment/elasticity/calculix_comparison.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "deformation_enrichment/elasticity/compressible_neo_hookean.hpp"
#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/root_mean_square.hpp"
#include "deformation_enrichment/seconds_since.hpp"

namespace deformation_enrichment::elasticity {
namespace {

using Clock = std::chrono::steady_clock;

TetFem makeSnhBody(const CalculixModel& model, SnhVariant variant) {
  std::vector<StableNeoHookean> materials;
  for (const IsotropicMaterial& m : model.materials) {
    const LameParameters lame = lameFromYoungPoisson(m.youngModulus, m.poissonRatio);
    materials.emplace_back(lame.mu, lame.lambda, variant);
  }
  return TetFem(model.rest, std::move(materials), model.materialId);
}

// The constraints ramped linearly from rest, as ccx ramps a static step: step k of n holds
// rest + k/n (target - rest). A hyperelastic equilibrium does not depend on the path, so the steps only
// keep Newton in its basin.
Eigen::Matrix3Xd solveOurs(const TetFem& fem, const CalculixModel& model, const CalculixComparisonOptions& options,
                           CalculixComparison& out) {
  SolverOptions settings;
  settings.relativeForceTolerance = options.relativeForceTolerance;
  settings.maxIterations = 200;
  QuasiStaticSolver solver(fem, settings);
  const DirichletConstraints& target = model.constraints;
  Eigen::Matrix3Xd restOfConstrained(3, target.positions.cols());
  for (std::size_t k = 0; k < target.vertices.size(); ++k)
    restOfConstrained.col(static_cast<Eigen::Index>(k)) = model.rest.vertices.col(target.vertices[k]);
  Eigen::Matrix3Xd x = model.rest.vertices;
  const auto start = Clock::now();
  for (int step = 1; step <= model.increments; ++step) {
    DirichletConstraints constraints;
    constraints.vertices = target.vertices;
    constraints.positions = restOfConstrained + (static_cast<double>(step) / model.increments) * (target.positions - restOfConstrained);
    const SolveResult result = solver.solve(x, constraints);
    out.ourIterations += result.iterations;
    if (!result.converged())
      throw NumericalError("compareWithCalculix: our solver did not converge in step " + std::to_string(step) + " of " +
                           std::to_string(model.increments) + ": " + result.message);
  }
  out.ourSeconds = secondsSince(start);
  return x - model.rest.vertices;
}

// Peak |principal Green strain| and peak |F - I|_2 over the tets at x.
void strainPeaks(const TetFem& fem, const Eigen::Matrix3Xd& x, CalculixComparison& out) {
  for (Eigen::Index t = 0; t < fem.numTets(); ++t) {
    const Eigen::Matrix3d F = fem.deformationGradient(x, t);
    const Eigen::Matrix3d green = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    out.maxGreenStrain = std::max(out.maxGreenStrain, symmetricEigen3(green).values.cwiseAbs().maxCoeff());
    const Eigen::Matrix3d D = F - Eigen::Matrix3d::Identity();
    const double largest = symmetricEigen3(D.transpose() * D).values.maxCoeff();
    out.maxDisplacementGradient = std::max(out.maxDisplacementGradient, std::sqrt(std::max(largest, 0.0)));
  }
}

// The SNH Hessian at x over the free dofs, factorised: exact if that factorises, else PSD-projected.
void factorise(const TetFem& fem, const Eigen::Matrix3Xd& x, const Eigen::VectorXi& dofMap,
               Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>& ldlt) {
  Eigen::SparseMatrix<double> H = fem.reducedPattern(dofMap, true);
  for (HessianKind kind : {HessianKind::Exact, HessianKind::Projected}) {
    fem.assembleReduced(x, dofMap, true, kind, H, nullptr);
    ldlt.compute(H);
    if (ldlt.info() == Eigen::Success) return;
  }
  throw NumericalError("compareWithCalculix: the SNH Hessian at the CalculiX solution does not factorise");
}

// One Newton step of the SNH energy from u_ccx driven only by the force the two energy forms differ by,
// g_snh - g_nh at u_ccx (both energies' forces on the same mesh): what the energy forms alone move ccx's
// answer by, to first order. What ccx leaves unbalanced in its own energy, g_nh(u_ccx), is not used.
void attributeToEnergyForms(const TetFem& fem, const CalculixModel& model, CalculixComparison& out) {
  const Eigen::Matrix3Xd x = model.rest.vertices + out.calculixDisplacements;
  int freeCount = 0;
  const Eigen::VectorXi dofMap = makeDofMap(model.rest.numVertices(), model.constraints.vertices, &freeCount);
  std::vector<CompressibleNeoHookean> neoHooke;
  for (const IsotropicMaterial& m : model.materials) {
    const LameParameters lame = lameFromYoungPoisson(m.youngModulus, m.poissonRatio);
    neoHooke.emplace_back(lame.mu, lame.lambda + 2.0 / 3.0 * lame.mu);
  }
  const Eigen::VectorXd gNh = neoHookeanGradient(fem, neoHooke, model.materialId, x);
  const Eigen::VectorXd gSnh = fem.gradient(x);
  Eigen::VectorXd formForce(freeCount), ccxResidual(freeCount);
  for (Eigen::Index d = 0; d < dofMap.size(); ++d) {
    if (dofMap[d] < 0) continue;
    formForce[dofMap[d]] = gSnh[d] - gNh[d];
    ccxResidual[dofMap[d]] = gNh[d];
  }
  out.calculixResidualRatio = formForce.norm() > 0.0 ? ccxResidual.norm() / formForce.norm() : 0.0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  factorise(fem, x, dofMap, ldlt);
  const Eigen::VectorXd du = ldlt.solve(-formForce);
  Eigen::Matrix3Xd corrected = out.calculixDisplacements;
  for (Eigen::Index d = 0; d < dofMap.size(); ++d)
    if (dofMap[d] >= 0) corrected(d % 3, d / 3) += du[dofMap[d]];
  out.energyFormRemainder = rootMeanSquare(corrected - out.ourDisplacements) / out.rmsDisplacement;
}

}  // namespace

CalculixComparison compareWithCalculix(const CalculixModel& model, const CalculixComparisonOptions& options) {
  validate(model);
  bool moves = false;
  for (std::size_t k = 0; k < model.constraints.vertices.size(); ++k)
    moves = moves || model.constraints.positions.col(static_cast<Eigen::Index>(k)) !=
                         model.rest.vertices.col(model.constraints.vertices[k]);
  if (!moves) throw InvalidInputError("compareWithCalculix: the constraints move no vertex, nothing to compare");
  const TetFem fem = makeSnhBody(model, options.variant);
  CalculixComparison out;
  out.ourDisplacements = solveOurs(fem, model, options, out);
  const CalculixRun run = runCalculix(model, options.calculix);
  out.calculixDisplacements = run.displacements;
  out.calculixSeconds = run.seconds;
  // RMS_v |u_ours - u_ccx| / RMS_v |u_ours| (the figure the check bounds).
  out.rmsDisplacement = rootMeanSquare(out.ourDisplacements);
  const Eigen::Matrix3Xd difference = out.ourDisplacements - out.calculixDisplacements;
  out.relativeDifference = rootMeanSquare(difference) / out.rmsDisplacement;
  out.maxDifference = difference.colwise().norm().maxCoeff();
  strainPeaks(fem, model.rest.vertices + out.ourDisplacements, out);
  attributeToEnergyForms(fem, model, out);
  return out;
}

}  // namespace deformation_enrichment::elasticity
