#include "deformation_enrichment/enrichment/descriptor_order.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

hermite::MomentList truncatedMoments(const hermite::MomentList& moments, int lastOrder) {
  if (lastOrder < moments.firstOrder() || lastOrder > moments.lastOrder())
    throw InvalidInputError("truncatedMoments: order " + std::to_string(lastOrder) + " outside the stored orders " +
                            std::to_string(moments.firstOrder()) + ".." + std::to_string(moments.lastOrder()));
  hermite::MomentList result(moments.firstOrder(), lastOrder, moments.channels());
  for (int c = 0; c < moments.channels(); ++c)
    for (int n = moments.firstOrder(); n <= lastOrder; ++n) result.order(n, c) = moments.order(n, c);
  return result;
}

int deformationOrder(const examples::ExampleSet& set) {
  if (set.examples.empty()) throw InvalidInputError("deformationOrder: the example set is empty");
  const hermite::MomentList& first = set.examples.front().mu;
  for (std::size_t i = 1; i < set.examples.size(); ++i) {
    const hermite::MomentList& mu = set.examples[i].mu;
    if (mu.firstOrder() != first.firstOrder() || mu.lastOrder() != first.lastOrder() || mu.channels() != first.channels())
      throw InvalidInputError("deformationOrder: example " + std::to_string(i) + " stores mu orders " +
                              std::to_string(mu.firstOrder()) + ".." + std::to_string(mu.lastOrder()) +
                              ", example 0 orders " + std::to_string(first.firstOrder()) + ".." +
                              std::to_string(first.lastOrder()));
  }
  return first.lastOrder();
}

examples::ExampleSet withDeformationOrder(const examples::ExampleSet& set, int order) {
  const int built = deformationOrder(set);
  if (order < 1 || order > built)
    throw InvalidInputError("Hermite order " + std::to_string(order) + " is not available: the example set stores " +
                            "mu orders 1.." + std::to_string(built));
  examples::ExampleSet result = set;
  if (order == built) return result;
  for (auto& example : result.examples) example.mu = truncatedMoments(example.mu, order);
  return result;
}

}  // namespace deformation_enrichment::enrichment
