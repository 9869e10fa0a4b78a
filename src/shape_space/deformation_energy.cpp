#include "deformation_enrichment/shape_space/deformation_energy.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "deformation_enrichment/error.hpp"
#include "parallel_for.hpp"

namespace deformation_enrichment::shape_space {

namespace {
void checkSizeAndFinite(const Eigen::VectorXd& shape, Eigen::Index numVertices, const char* name) {
  if (shape.size() != 3 * numVertices) {
    throw InvalidInputError(std::string("DeformationEnergy: ") + name + " shape has " +
                            std::to_string(shape.size()) + " entries, expected 3 x " +
                            std::to_string(numVertices) + " vertices");
  }
  for (Eigen::Index i = 0; i < shape.size(); ++i) {
    if (!std::isfinite(shape[i])) {
      throw InvalidInputError(std::string("DeformationEnergy: ") + name + " shape has a non-finite coordinate at vertex " +
                              std::to_string(i / 3));
    }
  }
}

// evaluate's output `member` alone.
template <class T>
T single(const DeformationEnergy& energy, T* EnergyOutputs::*member, const Eigen::VectorXd& reference,
         const Eigen::VectorXd& deformed) {
  T result{};
  EnergyOutputs outputs;
  outputs.*member = &result;
  energy.evaluate(reference, deformed, outputs);
  return result;
}

}  // namespace

void DeformationEnergy::checkShapes(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  checkSizeAndFinite(reference, numVertices(), "reference");
  checkSizeAndFinite(deformed, numVertices(), "deformed");
}

void DeformationEnergy::checkShape(const Eigen::VectorXd& shape) const { checkSizeAndFinite(shape, numVertices(), "given"); }

double DeformationEnergy::value(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::value, reference, deformed);
}
Eigen::VectorXd DeformationEnergy::gradientDeformed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::gradientDeformed, reference, deformed);
}
Eigen::VectorXd DeformationEnergy::gradientReference(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::gradientReference, reference, deformed);
}
Eigen::SparseMatrix<double> DeformationEnergy::hessianDeformed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::hessianDeformed, reference, deformed);
}
Eigen::SparseMatrix<double> DeformationEnergy::hessianMixed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::hessianMixed, reference, deformed);
}
Eigen::SparseMatrix<double> DeformationEnergy::hessianReference(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return single(*this, &EnergyOutputs::hessianReference, reference, deformed);
}

std::unique_ptr<DeformationEnergy> DeformationEnergy::onTriangles(const Eigen::Matrix3Xi&, Eigen::Index) const {
  throw InvalidInputError("DeformationEnergy: this energy cannot be evaluated on another mesh (no ghost mesh)");
}

std::vector<double> DeformationEnergy::pathSegments(const std::vector<Eigen::VectorXd>& shapes, bool closed,
                                                    std::vector<Eigen::VectorXd>* gradients, bool endGradients) const {
  const int count = int(shapes.size());
  if (count < 2) throw InvalidInputError("path energy: a path needs at least 2 shapes, got " + std::to_string(count));
  const int segments = closed ? count : count - 1;
  const int passes = 2 * segments;  // pass 2s: W(x_s, x_s+1); pass 2s+1: W(x_s+1, x_s)
  std::vector<double> values(size_t(passes), 0.0);
  std::vector<Eigen::VectorXd> gradReference(gradients ? size_t(passes) : 0), gradDeformed(gradients ? size_t(passes) : 0);
  const auto shapesOf = [&](int p) {
    const int a = p / 2, b = (a + 1) % count;
    return p % 2 == 0 ? std::pair<int, int>{a, b} : std::pair<int, int>{b, a};
  };
  const auto wanted = [&](int k) { return gradients && (closed || endGradients || (k > 0 && k + 1 < count)); };
  detail::parallelFor(passes, numVertices() >= detail::kParallelVertices, [&](int p) {
    const auto [reference, deformed] = shapesOf(p);
    EnergyOutputs out;
    out.value = &values[size_t(p)];
    if (wanted(reference)) out.gradientReference = &gradReference[size_t(p)];
    if (wanted(deformed)) out.gradientDeformed = &gradDeformed[size_t(p)];
    evaluate(shapes[size_t(reference)], shapes[size_t(deformed)], out);
  });
  if (gradients) {
    gradients->assign(shapes.size(), Eigen::VectorXd::Zero(shapes.front().size()));
    for (int p = 0; p < passes; ++p) {
      const auto [reference, deformed] = shapesOf(p);
      if (wanted(reference)) (*gradients)[size_t(reference)] += gradReference[size_t(p)];
      if (wanted(deformed)) (*gradients)[size_t(deformed)] += gradDeformed[size_t(p)];
    }
  }
  std::vector<double> sums(static_cast<size_t>(segments));
  for (size_t s = 0; s < sums.size(); ++s) sums[s] = values[2 * s] + values[2 * s + 1];
  return sums;
}

std::unique_ptr<WeightedReferenceEnergy> DeformationEnergy::weightedReferences(
    const std::vector<double>&, const std::vector<const Eigen::VectorXd*>&, const std::vector<const ReferenceData*>&) const {
  return nullptr;
}

std::shared_ptr<const ReferenceData> DeformationEnergy::referenceData(const Eigen::VectorXd&) const { return nullptr; }

std::optional<double> DeformationEnergy::pathEnergy(const std::vector<const ReferenceData*>&, bool) const { return std::nullopt; }

}  // namespace deformation_enrichment::shape_space
