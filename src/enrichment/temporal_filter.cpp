#include "deformation_enrichment/enrichment/temporal_filter.hpp"

#include <cmath>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {
void checkTimeConstant(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds))
    throw InvalidInputError("temporal filter: the time constant must be >= 0 and finite (0 = off)");
}
}  // namespace

TemporalFilter::TemporalFilter(double timeConstant) : tau_(timeConstant) { checkTimeConstant(timeConstant); }

void TemporalFilter::setTimeConstant(double seconds) {
  checkTimeConstant(seconds);
  tau_ = seconds;
  reset();
}

void TemporalFilter::reset() {
  state_.resize(3, 0);
  active_.clear();
}

void TemporalFilter::filter(SurfaceEnrichment& field, double dt, Eigen::Index numVertices) {
  if (tau_ == 0.0 || state_.cols() != numVertices || !(dt > 0.0) || !std::isfinite(dt)) {
    if (tau_ == 0.0) return reset();
    state_ = Eigen::Matrix3Xd::Zero(3, numVertices);  // O(n), on a restart only
    for (std::size_t k = 0; k < field.vertices.size(); ++k)
      state_.col(field.vertices[k]) = field.displacements.col(static_cast<Eigen::Index>(k));
    active_ = field.vertices;
    return;
  }
  const double alpha = 1.0 - std::exp(-dt / tau_);
  std::vector<int> kept;
  kept.reserve(active_.size() + field.vertices.size());
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(active_.size() + field.vertices.size()));
  std::size_t a = 0, f = 0;
  while (a < active_.size() || f < field.vertices.size()) {  // merge of two ascending lists
    const bool fromField = f < field.vertices.size() && (a >= active_.size() || field.vertices[f] <= active_[a]);
    const int v = fromField ? field.vertices[f] : active_[a];
    if (a < active_.size() && active_[a] == v) ++a;
    const Eigen::Vector3d target = fromField ? Eigen::Vector3d(field.displacements.col(static_cast<Eigen::Index>(f++)))
                                             : Eigen::Vector3d::Zero();
    state_.col(v) += alpha * (target - state_.col(v));
    if (fromField || state_.col(v).squaredNorm() > kFloor * kFloor) {
      out.col(static_cast<Eigen::Index>(kept.size())) = state_.col(v);
      kept.push_back(v);
    } else {
      state_.col(v).setZero();
    }
  }
  field.displacements = out.leftCols(static_cast<Eigen::Index>(kept.size()));
  field.vertices = kept;
  active_ = std::move(kept);
}

}  // namespace deformation_enrichment::enrichment
