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

void evaluateBasis(const Eigen::Vector3d& r, int firstOrder, int lastOrder, double* out) {
  checkRange(firstOrder, lastOrder);
  const BasisTable& table = basisTable();
  // Univariate tables He_k(r_i), k <= lastOrder, then products per multi-index.
  double he[3][kMaxHermiteOrder + 1];
  for (int axis = 0; axis < 3; ++axis) {
    he[axis][0] = 1.0;
    if (lastOrder >= 1) he[axis][1] = r[axis];
    for (int k = 1; k < lastOrder; ++k) he[axis][k + 1] = r[axis] * he[axis][k] - k * he[axis][k - 1];
  }
  const int begin = orderOffset(firstOrder), end = orderOffset(lastOrder + 1);
  for (int c = begin; c < end; ++c) {
    const int* e = table.exponent[c];
    *out++ = table.scale[c] * he[0][e[0]] * he[1][e[1]] * he[2][e[2]];
  }
}

Eigen::VectorXd evaluateBasis(const Eigen::Vector3d& r, int firstOrder, int lastOrder) {
  Eigen::VectorXd values(basisSize(firstOrder, lastOrder));
  evaluateBasis(r, firstOrder, lastOrder, values.data());
  return values;
}

}  // namespace deformation_enrichment::hermite
