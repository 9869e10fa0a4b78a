#pragma once
// The reduced side of the smoothing flow ([Brandt16 §6], "Dimensional reduction"): one basis B shared by the
// shapes of a sequence (the PCA of the sequence, enriched by extra directions) and per shape the affine
// space x_i + B q through it. The averages are solved in the evaluation space (evaluation_space.hpp), over
// S x_i + S B q, and lifted to the fine mesh by the same coordinates q.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"
#include "deformation_enrichment/shape_space/reduced_average.hpp"

namespace deformation_enrichment::shape_space {

class ReducedSmoothingSpace {
public:
  /// B = the PCA of `shapes` (fine mesh, at most `dimension` directions) enriched by `directions`; each
  /// shape's space passes through the shape itself, so it is exactly representable. Every space needs a
  /// warm start (setWarmStart) before its first average. Throws InvalidInputError if the shapes span nothing.
  ReducedSmoothingSpace(const EvaluationSpace& space, const std::vector<Eigen::VectorXd>& shapes, int dimension,
                        const std::vector<Eigen::VectorXd>& directions);

  /// The columns of B: at most the dimension asked for, fewer if the shapes span fewer directions.
  Eigen::Index dimension() const { return fineBasis_->cols(); }
  /// |B^T v|^2 of a fine-mesh vector v.
  double squaredNormInBasis(const Eigen::VectorXd& fine) const;
  /// |(S B)^T v|^2 of an evaluation-space vector v.
  double squaredNormInEvaluatedBasis(const Eigen::VectorXd& evaluated) const;

  /// Starts shape i's quasi-Newton model at B^T hessian B made positive definite (hessian in the evaluation space).
  void setWarmStart(int i, const Eigen::SparseMatrix<double>& hessian);
  /// reducedElasticAverage over shape i's space from `initial` (arguments in the evaluation space), with its
  /// shape lifted to the fine mesh.
  AverageResult average(int i, const EvaluationSpace& space, const std::vector<double>& weights,
                        const std::vector<const Eigen::VectorXd*>& examples, const std::vector<const ReferenceData*>& data,
                        const Eigen::VectorXd& initial, const ReducedAverageOptions& options) const;
  /// Shape i moved to `fine` (fine mesh): its space passes through it from now on, and a non-empty `model`
  /// (the quasi-Newton model its last average ended with) is its next warm start.
  void moveTo(int i, const EvaluationSpace& space, const Eigen::VectorXd& fine, Eigen::MatrixXd model);

private:
  std::shared_ptr<const Eigen::MatrixXd> fineBasis_;  ///< B
  std::shared_ptr<const Eigen::MatrixXd> basis_;      ///< S B (B itself without a ghost mesh), shared by spaces_
  std::vector<Eigen::VectorXd> fineOrigins_;          ///< x_i
  std::vector<ReducedSpace> spaces_;                  ///< per shape: S x_i, S B and the warm start
};

}  // namespace deformation_enrichment::shape_space
