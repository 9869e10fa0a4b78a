#include "deformation_enrichment/hermite/symmetric_tensor.hpp"

#include <algorithm>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"

namespace deformation_enrichment::hermite {

namespace {
int power3(int n) {
  int p = 1;
  for (int k = 0; k < n; ++k) p *= 3;
  return p;
}

// Index tuple of a flat full-tensor entry, most significant index first.
void tupleOf(int flat, int order, int* tuple) {
  for (int k = order - 1; k >= 0; --k) {
    tuple[k] = flat % 3;
    flat /= 3;
  }
}

int componentOfTuple(const int* tuple, int order) {
  MultiIndex alpha{0, 0, 0};
  for (int k = 0; k < order; ++k) ++alpha[tuple[k]];
  return componentIndex(alpha);
}

// The sorted index tuple that represents component alpha.
void representativeTuple(const MultiIndex& alpha, int* tuple) {
  int position = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int c = 0; c < alpha[axis]; ++c) tuple[position++] = axis;
}

void checkSize(int order, Eigen::Index size, const char* what) {
  if (size != numComponents(order))
    throw InvalidInputError(std::string(what) + ": expected " + std::to_string(numComponents(order)) +
                            " distinct components for order " + std::to_string(order) + ", got " +
                            std::to_string(size));
}
}  // namespace

Eigen::VectorXd toFullTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& distinct) {
  checkSize(order, distinct.size(), "toFullTensor");
  const int entries = power3(order);
  Eigen::VectorXd full(entries);
  int tuple[kMaxHermiteOrder];
  for (int flat = 0; flat < entries; ++flat) {
    tupleOf(flat, order, tuple);
    full[flat] = distinct[componentOfTuple(tuple, order)];
  }
  return full;
}

Eigen::VectorXd fromFullTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& full) {
  const int entries = power3(std::clamp(order, 0, kMaxHermiteOrder));
  if (full.size() != entries || order < 0 || order > kMaxHermiteOrder)
    throw InvalidInputError("fromFullTensor: expected 3^" + std::to_string(order) + " entries, got " +
                            std::to_string(full.size()));
  const auto& alphas = multiIndices(order);
  Eigen::VectorXd distinct(alphas.size());
  int tuple[kMaxHermiteOrder];
  for (std::size_t c = 0; c < alphas.size(); ++c) {
    representativeTuple(alphas[c], tuple);
    int flat = 0;
    for (int k = 0; k < order; ++k) flat = 3 * flat + tuple[k];
    distinct[c] = full[flat];
  }
  return distinct;
}

double fullTensorDot(int order, const Eigen::Ref<const Eigen::VectorXd>& a,
                     const Eigen::Ref<const Eigen::VectorXd>& b) {
  checkSize(order, a.size(), "fullTensorDot");
  checkSize(order, b.size(), "fullTensorDot");
  const auto& alphas = multiIndices(order);
  double sum = 0.0;
  // Appendix A: every full-tensor entry of component alpha repeats it multiplicity(alpha) times.
  for (std::size_t c = 0; c < alphas.size(); ++c) sum += multiplicity(alphas[c]) * a[c] * b[c];
  return sum;
}

Eigen::MatrixXd symmetricTransform(int order, const Eigen::Matrix3d& T) {
  if (!T.allFinite()) throw InvalidInputError("symmetricTransform: transformation is not finite");
  const auto& alphas = multiIndices(order);
  const int k = static_cast<int>(alphas.size());
  const int entries = power3(order);
  Eigen::MatrixXd map = Eigen::MatrixXd::Zero(k, k);
  int outTuple[kMaxHermiteOrder];
  int inTuple[kMaxHermiteOrder];
  for (int row = 0; row < k; ++row) {
    representativeTuple(alphas[row], outTuple);
    // Appendix B: sum over all input tuples j, grouped by the distinct component they read.
    for (int flat = 0; flat < entries; ++flat) {
      tupleOf(flat, order, inTuple);
      double product = 1.0;
      for (int m = 0; m < order; ++m) product *= T(outTuple[m], inTuple[m]);
      map(row, componentOfTuple(inTuple, order)) += product;
    }
  }
  return map;
}

Eigen::VectorXd transformTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& distinct,
                                const Eigen::Matrix3d& T) {
  checkSize(order, distinct.size(), "transformTensor");
  return symmetricTransform(order, T) * distinct;
}

}  // namespace deformation_enrichment::hermite
