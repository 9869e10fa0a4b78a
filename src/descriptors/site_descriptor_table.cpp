#include "deformation_enrichment/descriptors/site_descriptor_table.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

SiteDescriptorTable::SiteDescriptorTable(const DescriptorEvaluator& evaluator) : evaluator_(&evaluator) {
  const mesh::TriangleMesh& surface = evaluator.surface();
  sites_.resize(surface.numVertices());
  // Independent per vertex; the KD-tree queries are read-only.
#pragma omp parallel for schedule(dynamic, 64)
  for (Eigen::Index v = 0; v < surface.numVertices(); ++v) sites_[v] = evaluator.evaluate(surface.vertices.col(v));
}

const ContactDescriptor& SiteDescriptorTable::atVertex(Eigen::Index v) const {
  if (v < 0 || v >= size())
    throw InvalidInputError("site table: vertex " + std::to_string(v) + " outside [0, " + std::to_string(size()) + ")");
  return sites_[v];
}

const ContactDescriptor& SiteDescriptorTable::nearest(const Eigen::Vector3d& p) const {
  return sites_[evaluator_->nearestSurfaceVertex(p)];
}

std::vector<hermite::MomentList> SiteDescriptorTable::framedDescriptors() const {
  std::vector<hermite::MomentList> framed;
  framed.reserve(sites_.size());
  for (const ContactDescriptor& site : sites_) framed.push_back(site.rho);
  return framed;
}

}  // namespace deformation_enrichment::descriptors
