#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace deformation_enrichment::descriptors {

namespace {
void checkOptions(const DescriptorOptions& options) {
  if (options.siteOrder < 1 || options.siteOrder > hermite::kMaxHermiteOrder)
    throw InvalidInputError("site descriptor order " + std::to_string(options.siteOrder) +
                            " outside [1, 4] (order 1 defines the stamping frame)");
  if (options.deformationOrder < 1 || options.deformationOrder > hermite::kMaxHermiteOrder)
    throw InvalidInputError("deformation descriptor order " + std::to_string(options.deformationOrder) +
                            " outside [1, 4]");
}

mesh::TetSurface surfaceOf(const mesh::TetMesh& rest) {
  mesh::validate(rest, true);
  return mesh::extractSurface(rest);
}

DescriptorEvaluator fromTets(const mesh::TetMesh& rest, const DescriptorOptions& options) {
  mesh::TetSurface boundary = surfaceOf(rest);
  return DescriptorEvaluator(PointSampling::fromTetMesh(rest), std::move(boundary.surface),
                             std::move(boundary.surfaceToVolume), options);
}
}  // namespace

DescriptorEvaluator::DescriptorEvaluator(const mesh::TetMesh& rest, const DescriptorOptions& options)
    : DescriptorEvaluator(fromTets(rest, options)) {}

DescriptorEvaluator::DescriptorEvaluator(PointSampling sampling, mesh::TriangleMesh surface,
                                         std::vector<int> surfaceToSample, const DescriptorOptions& options)
    : options_(options),
      sampling_(std::move(sampling)),
      surface_(std::move(surface)),
      surfaceToSample_(std::move(surfaceToSample)),
      surfaceNormals_(),
      surfaceIndex_((mesh::validate(surface_, false), surface_.vertices),
                    Eigen::VectorXd::Zero(surface_.numVertices())) {
  checkOptions(options_);
  if (!surfaceToSample_.empty()) {
    if (static_cast<Eigen::Index>(surfaceToSample_.size()) != surface_.numVertices())
      throw InvalidInputError("descriptor evaluator: surface-to-sample map has wrong size");
    for (int index : surfaceToSample_)
      if (index < 0 || index >= sampling_.size())
        throw InvalidInputError("descriptor evaluator: surface vertex maps outside the samples");
  }
  surfaceNormals_ = mesh::vertexNormals(surface_);
}

Eigen::Vector3d DescriptorEvaluator::normalAt(const Eigen::Vector3d& p) const {
  return surfaceNormals_.col(surfaceIndex_.nearest(p));
}

ContactDescriptor DescriptorEvaluator::evaluate(const Eigen::Vector3d& p) const {
  ContactDescriptor result;
  result.p = p;
  const Window window = gatherWindow(sampling_, p, options_.window);
  result.normal = normalAt(p);
  result.rhoWorld = densityMoments(window, 0, options_.siteOrder);
  result.frame = stampingFrame(result.normal, result.rhoWorld, nullptr, options_.frameTolerance);
  result.rho = result.rhoWorld.transformed(result.frame.B.transpose());  // world -> frame B (Appendix B)
  return result;
}

ContactDescriptor DescriptorEvaluator::evaluate(const Eigen::Vector3d& p,
                                                const Eigen::Matrix3Xd& deformedSamples) const {
  if (deformedSamples.cols() != sampling_.size())
    throw InvalidInputError("descriptor evaluator: " + std::to_string(deformedSamples.cols()) +
                            " deformed positions for " + std::to_string(sampling_.size()) + " samples");
  ContactDescriptor result;
  result.p = p;
  const Window window = gatherWindow(sampling_, p, options_.window);
  result.normal = normalAt(p);
  result.rhoWorld = densityMoments(window, 0, options_.siteOrder);

  // The samples fill the volume (tet vertices or an interior grid): the plain shape-matching fit. The
  // normal-completed surface mode of kinematics/ is for surface-only samples (deformationDescriptor).
  result.deformation =
      deformationDescriptor(window, sampling_.points(), deformedSamples, options_.deformationOrder, nullptr,
                            nullptr, options_.mls);
  result.frame = stampingFrame(result.normal, result.rhoWorld, &result.deformation->mu, options_.frameTolerance);
  const Eigen::Matrix3d toFrame = result.frame.B.transpose();
  result.rho = result.rhoWorld.transformed(toFrame);
  result.mu = result.deformation->mu.transformed(toFrame);
  return result;
}

}  // namespace deformation_enrichment::descriptors
