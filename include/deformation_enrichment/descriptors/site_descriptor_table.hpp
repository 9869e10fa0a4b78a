#pragma once
// Site descriptors depend on the rest shape only (docs/design.md §4): computed once for every surface vertex,
// then looked up at a contact instead of recomputed per frame.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"

namespace deformation_enrichment::descriptors {

class SiteDescriptorTable {
public:
  /// Evaluates rho, the stamping frame and rho in that frame at every surface vertex of the evaluator
  /// (OpenMP over vertices). The evaluator must outlive the table.
  explicit SiteDescriptorTable(const DescriptorEvaluator& evaluator);

  Eigen::Index size() const { return static_cast<Eigen::Index>(sites_.size()); }
  /// Descriptor of surface vertex v (throws InvalidInputError when out of range).
  const ContactDescriptor& atVertex(Eigen::Index v) const;
  /// Descriptor of the surface vertex nearest to p (the contact's site, without a new moment sum).
  const ContactDescriptor& nearest(const Eigen::Vector3d& p) const;
  /// Site descriptors in their frames, in surface-vertex order (the input of k-means).
  std::vector<hermite::MomentList> framedDescriptors() const;

private:
  const DescriptorEvaluator* evaluator_;
  std::vector<ContactDescriptor> sites_;
};

}  // namespace deformation_enrichment::descriptors
