#include "deformation_enrichment/hermite/multi_index.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::hermite {

namespace {
void checkOrder(int order) {
  if (order < 0 || order > kMaxHermiteOrder)
    throw InvalidInputError("Hermite order " + std::to_string(order) + " outside [0, " +
                            std::to_string(kMaxHermiteOrder) + "]");
}

// Sorted index tuples i1 <= ... <= in in lexicographic order map one-to-one to multi-indices; walking the
// tuples in that order gives the documented component order.
void appendSortedTuples(int remaining, int minAxis, MultiIndex& counts, std::vector<MultiIndex>& out) {
  if (remaining == 0) {
    out.push_back(counts);
    return;
  }
  for (int axis = minAxis; axis < 3; ++axis) {
    ++counts[axis];
    appendSortedTuples(remaining - 1, axis, counts, out);
    --counts[axis];
  }
}

std::array<std::vector<MultiIndex>, kMaxHermiteOrder + 1> buildTable() {
  std::array<std::vector<MultiIndex>, kMaxHermiteOrder + 1> table;
  for (int n = 0; n <= kMaxHermiteOrder; ++n) {
    MultiIndex counts{0, 0, 0};
    appendSortedTuples(n, 0, counts, table[n]);
  }
  return table;
}
}  // namespace

int numComponents(int order) {
  checkOrder(order);
  return (order + 1) * (order + 2) / 2;
}

const std::vector<MultiIndex>& multiIndices(int order) {
  checkOrder(order);
  static const auto table = buildTable();
  return table[order];
}

double factorial(int n) {
  double f = 1.0;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

double multiplicity(const MultiIndex& alpha) {
  return factorial(alpha[0] + alpha[1] + alpha[2]) /
         (factorial(alpha[0]) * factorial(alpha[1]) * factorial(alpha[2]));
}

int componentIndex(const MultiIndex& alpha) {
  const int n = alpha[0] + alpha[1] + alpha[2];
  const auto& list = multiIndices(n);
  for (int k = 0; k < static_cast<int>(list.size()); ++k)
    if (list[k] == alpha) return k;
  throw InvalidInputError("invalid multi-index");
}

}  // namespace deformation_enrichment::hermite
