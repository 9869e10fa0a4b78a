#include "deformation_enrichment/hermite/hermite_basis.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"

namespace deformation_enrichment::hermite {

namespace {
void checkRange(int firstOrder, int lastOrder) {
  if (firstOrder < 0 || lastOrder > kMaxHermiteOrder || firstOrder > lastOrder)
    throw InvalidInputError("Hermite order range [" + std::to_string(firstOrder) + ", " +
                            std::to_string(lastOrder) + "] invalid (orders 0.." +
                            std::to_string(kMaxHermiteOrder) + ")");
}
}  // namespace

double gaussianWindow(double squaredRadius) {
  // eq. (2)
  static const double kNormalisation = std::pow(2.0 * M_PI, -1.5);
  return kNormalisation * std::exp(-0.5 * squaredRadius);
}

double hermiteHe(int k, double x) {
  if (k < 0) throw InvalidInputError("Hermite degree " + std::to_string(k) + " is negative");
  double previous = 1.0;  // He_0
  if (k == 0) return previous;
  double current = x;  // He_1
  for (int j = 1; j < k; ++j) {
    const double next = x * current - j * previous;
    previous = current;
    current = next;
  }
  return current;
}

int basisSize(int firstOrder, int lastOrder) {
  checkRange(firstOrder, lastOrder);
  return orderOffset(lastOrder + 1) - orderOffset(firstOrder);
}

namespace {
// Flattened multi-index table of orders 0..kMaxHermiteOrder and the 1/sqrt(n!) factors, built once so the
// per-sample loop touches only small contiguous arrays.
struct BasisTable {
  static constexpr int kSize = (kMaxHermiteOrder + 1) * (kMaxHermiteOrder + 2) * (kMaxHermiteOrder + 3) / 6;
  int exponent[kSize][3];
  double scale[kSize];
  BasisTable() {
    int position = 0;
    for (int n = 0; n <= kMaxHermiteOrder; ++n)
      for (const MultiIndex& alpha : multiIndices(n)) {
        for (int axis = 0; axis < 3; ++axis) exponent[position][axis] = alpha[axis];
        scale[position] = 1.0 / std::sqrt(factorial(n));  // eq. (3): 1/sqrt(n!)
        ++position;
      }
  }
};
const BasisTable& basisTable() {
  static const BasisTable table;
  return table;
}
}  // namespace

void evaluateBasis(const Eigen::Ref<const Eigen::Matrix3Xd>& r, int firstOrder, int lastOrder, Eigen::MatrixXd& out) {
  checkRange(firstOrder, lastOrder);
  const BasisTable& table = basisTable();
  const Eigen::Index count = r.cols();
  // Univariate tables He_k(r_i) of every sample, k <= lastOrder (a column per k), then a product of three
  // columns per multi-index: each step runs over all samples at once.
  Eigen::ArrayXXd he[3];
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::ArrayXXd& h = he[axis];
    h.resize(count, lastOrder + 1);
    h.col(0).setOnes();
    if (lastOrder >= 1) h.col(1) = r.row(axis).transpose().array();
    for (int k = 1; k < lastOrder; ++k) h.col(k + 1) = h.col(1) * h.col(k) - k * h.col(k - 1);
  }
  const int begin = orderOffset(firstOrder), end = orderOffset(lastOrder + 1);
  out.resize(count, end - begin);
  for (int c = begin; c < end; ++c) {
    const int* e = table.exponent[c];
    out.col(c - begin) = table.scale[c] * he[0].col(e[0]) * he[1].col(e[1]) * he[2].col(e[2]);
  }
}

Eigen::VectorXd evaluateBasis(const Eigen::Vector3d& r, int firstOrder, int lastOrder) {
  Eigen::MatrixXd values;
  evaluateBasis(Eigen::Matrix3Xd(r), firstOrder, lastOrder, values);
  return values.row(0).transpose();
}

}  // namespace deformation_enrichment::hermite
