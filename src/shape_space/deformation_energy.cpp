#include "deformation_enrichment/shape_space/deformation_energy.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

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
}  // namespace

void DeformationEnergy::checkShapes(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  checkSizeAndFinite(reference, numVertices(), "reference");
  checkSizeAndFinite(deformed, numVertices(), "deformed");
}

void DeformationEnergy::checkShape(const Eigen::VectorXd& shape) const { checkSizeAndFinite(shape, numVertices(), "given"); }

void DeformationEnergy::evaluate(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed,
                                 const EnergyOutputs& outputs) const {
  if (outputs.value) *outputs.value = value(reference, deformed);
  if (outputs.gradientDeformed) *outputs.gradientDeformed = gradientDeformed(reference, deformed);
  if (outputs.gradientReference) *outputs.gradientReference = gradientReference(reference, deformed);
  if (outputs.hessianDeformed) *outputs.hessianDeformed = hessianDeformed(reference, deformed);
  if (outputs.hessianMixed) *outputs.hessianMixed = hessianMixed(reference, deformed);
  if (outputs.hessianReference) *outputs.hessianReference = hessianReference(reference, deformed);
}

std::unique_ptr<DeformationEnergy> DeformationEnergy::onTriangles(const Eigen::Matrix3Xi&, Eigen::Index) const {
  throw InvalidInputError("DeformationEnergy: this energy cannot be evaluated on another mesh (no ghost mesh)");
}

std::unique_ptr<WeightedReferenceEnergy> DeformationEnergy::weightedReferences(
    const std::vector<double>&, const std::vector<const Eigen::VectorXd*>&) const {
  return nullptr;
}

}  // namespace deformation_enrichment::shape_space
