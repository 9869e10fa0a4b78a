#include "deformation_enrichment/shape_space/reduced_smoothing_space.hpp"

#include <utility>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/affine_subspace.hpp"

namespace deformation_enrichment::shape_space {
namespace {

// The first step's warm start: ridge relative to the mean diagonal (its Hessian's rigid null space is the
// objective's at its start).
constexpr double kObjectiveWarmStartRidge = 1e-5;

}  // namespace

ReducedSmoothingSpace::ReducedSmoothingSpace(const EvaluationSpace& space, const std::vector<Eigen::VectorXd>& shapes,
                                             int dimension, const std::vector<Eigen::VectorXd>& directions) {
  AffineSubspace pca = pcaSubspace(shapes, dimension);
  enrich(pca, directions);
  if (pca.dimension() == 0) throw InvalidInputError("flow: the shapes span no subspace (all identical?)");
  fineBasis_ = std::make_shared<const Eigen::MatrixXd>(std::move(pca.basis));
  basis_ = space.ghost() ? std::make_shared<const Eigen::MatrixXd>(space.restrictRows(*fineBasis_)) : fineBasis_;
  fineOrigins_ = shapes;
  spaces_.resize(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i) {
    spaces_[i].origin = space.restrict(shapes[i]);
    spaces_[i].basis = basis_;
  }
}

double ReducedSmoothingSpace::squaredNormInBasis(const Eigen::VectorXd& fine) const {
  return (fineBasis_->transpose() * fine).squaredNorm();
}

double ReducedSmoothingSpace::squaredNormInEvaluatedBasis(const Eigen::VectorXd& evaluated) const {
  return (basis_->transpose() * evaluated).squaredNorm();
}

void ReducedSmoothingSpace::setWarmStart(int i, const Eigen::SparseMatrix<double>& hessian) {
  shape_space::setWarmStart(spaces_[size_t(i)], hessian, kObjectiveWarmStartRidge);
}

AverageResult ReducedSmoothingSpace::average(int i, const EvaluationSpace& space, const std::vector<double>& weights,
                                             const std::vector<const Eigen::VectorXd*>& examples,
                                             const std::vector<const ReferenceData*>& data, const Eigen::VectorXd& initial,
                                             const ReducedAverageOptions& options) const {
  AverageResult result = reducedElasticAverage(space.energy(), weights, examples, spaces_[size_t(i)], initial, options, data);
  // Same reduced coordinates on the fine mesh (exact lift without a ghost mesh).
  if (space.ghost()) result.shape = fineOrigins_[size_t(i)] + *fineBasis_ * result.reducedCoordinates;
  return result;
}

void ReducedSmoothingSpace::moveTo(int i, const EvaluationSpace& space, const Eigen::VectorXd& fine, Eigen::MatrixXd model) {
  // Origin at the moved shape, same basis ([Brandt16 §6]: the space of shape i passes through x_i).
  fineOrigins_[size_t(i)] = fine;
  spaces_[size_t(i)].origin = space.restrict(fine);
  // The next average of this shape is a similar problem: its solver starts from the model this one ended
  // with (measured on a 24-frame bent elephant: 70-119 instead of 148-166 iterations per step after the
  // first, eq. 4 the same to 4 digits).
  if (model.size() > 0) spaces_[size_t(i)].warmStart = std::move(model);
}

}  // namespace deformation_enrichment::shape_space
