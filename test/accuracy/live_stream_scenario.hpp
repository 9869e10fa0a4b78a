#pragma once
// The live-stream scenario (docs/accuracy.md), shared by live_stream_check (the run-time pipeline in one process)
// and the live_stream rostest (the same frames through the running node): a closed box surface of the
// slab's size, meshed at a given vertex spacing, carries a coarse dent (Gaussian, 3 mm deep) that is
// pressed, slid along x at a given speed per frame, held, released by the tool while the tissue is still
// dented, then relaxed back to rest. StreamMeter turns the frames' added detail into these measures:
//   flicker   max over the slide and hold frames of |d_t - d_t-1| / max(|d_t|, |d_t-1|) for the added detail
//             d, divided by the same measure of the coarse dent c = coarse - rest (bound 3);
//   retained  |d| on the first frame after lift-off over |d| on the frame before (bound 0.5);
//   residual  the largest |d| from the third frame back at rest on, over |d| before lift-off (bound 0.05).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace live_stream {

constexpr double kTop = 0.02, kDepth = 0.003, kSigma = 0.006, kSlide = 0.008, kFramePeriod = 1.0 / 60.0;
constexpr double kMaxFlicker = 1.5, kMinRetained = 0.5, kMaxResidual = 0.05;

struct Frame {
  double x = 0.0, depth = 0.0;
  bool touching = false;
  enum Phase { Press, Slide, Hold, Lifted, Relax, Rest } phase = Press;
};

inline std::vector<Frame> sequence(double speed) {
  std::vector<Frame> frames;
  const double start = -kSlide / 2;
  for (int k = 1; k <= 10; ++k) frames.push_back({start, kDepth * k / 10.0, true, Frame::Press});
  const int slideFrames = static_cast<int>(std::lround(kSlide / speed));
  for (int k = 1; k <= slideFrames; ++k) frames.push_back({start + kSlide * k / slideFrames, kDepth, true, Frame::Slide});
  for (int k = 0; k < 5; ++k) frames.push_back({kSlide / 2, kDepth, true, Frame::Hold});
  for (int k = 0; k < 5; ++k) frames.push_back({kSlide / 2, kDepth, false, Frame::Lifted});
  for (int k = 1; k <= 10; ++k) frames.push_back({kSlide / 2, kDepth * (1.0 - k / 10.0), false, Frame::Relax});
  for (int k = 0; k < 5; ++k) frames.push_back({kSlide / 2, 0.0, false, Frame::Rest});
  return frames;
}

/// The closed box surface (10 x 10 x 2 cm, top at z = kTop) meshed at about `spacing`.
inline deformation_enrichment::mesh::TriangleMesh boxSurface(double spacing) {
  namespace mesh = deformation_enrichment::mesh;
  const auto cells = [&](double length) { return std::max(1, static_cast<int>(std::lround(length / spacing))); };
  return mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, kTop),
                                                Eigen::Vector3i(cells(0.1), cells(0.1), cells(kTop))))
      .surface;
}

/// The coarse state: a smooth dent under (x, 0, top), fading with depth into the slab.
inline Eigen::Matrix3Xd coarseState(const Eigen::Matrix3Xd& rest, const Frame& f) {
  Eigen::Matrix3Xd x = rest;
  const Eigen::Vector3d centre(f.x, 0.0, kTop);
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    x(2, v) -= f.depth * std::exp(-(rest.col(v) - centre).squaredNorm() / (2 * kSigma * kSigma)) * rest(2, v) / kTop;
  return x;
}

/// Where the tool tip is: on the dented surface while touching, 2 cm above it once lifted.
inline Eigen::Vector3d toolPoint(const Frame& f) {
  return f.touching ? Eigen::Vector3d(f.x, 0.0, kTop - f.depth) : Eigen::Vector3d(f.x, 0.0, kTop + 0.02);
}

inline double relativeChange(const Eigen::Matrix3Xd& now, const Eigen::Matrix3Xd& before) {
  const double size = std::max(now.norm(), before.norm());
  return size > 0.0 ? (now - before).norm() / size : 0.0;
}

struct Measures {
  double detailFlicker = 0.0, coarseFlicker = 0.0, retained = 0.0, residual = 0.0;
  double flickerRatio() const { return coarseFlicker > 0.0 ? detailFlicker / coarseFlicker : 0.0; }
  bool withinBounds(double maxFlicker = kMaxFlicker, double minRetained = kMinRetained, double maxResidual = kMaxResidual) const {
    return flickerRatio() <= maxFlicker && retained >= minRetained && residual <= maxResidual;
  }
};

/// Accumulates the measures frame by frame, in the order of sequence().
class StreamMeter {
public:
  explicit StreamMeter(Eigen::Index vertices)
      : previousDetail_(Eigen::Matrix3Xd::Zero(3, vertices)), previousDent_(previousDetail_) {}

  /// `detail` = enriched - coarse, `dent` = coarse - rest of frame `f`.
  void add(const Frame& f, const Eigen::Matrix3Xd& detail, const Eigen::Matrix3Xd& dent) {
    if (f.phase == Frame::Slide || f.phase == Frame::Hold) {
      m_.detailFlicker = std::max(m_.detailFlicker, relativeChange(detail, previousDetail_));
      m_.coarseFlicker = std::max(m_.coarseFlicker, relativeChange(dent, previousDent_));
    }
    if (f.phase == Frame::Lifted && previousPhase_ == Frame::Hold) {
      beforeLiftOff_ = previousDetail_.norm();
      m_.retained = beforeLiftOff_ > 0.0 ? detail.norm() / beforeLiftOff_ : 0.0;
    }
    if (f.phase == Frame::Rest && ++restFrames_ >= 3 && beforeLiftOff_ > 0.0)
      m_.residual = std::max(m_.residual, detail.norm() / beforeLiftOff_);
    previousDetail_ = detail;
    previousDent_ = dent;
    previousPhase_ = f.phase;
  }

  const Measures& measures() const { return m_; }

private:
  Measures m_;
  Eigen::Matrix3Xd previousDetail_, previousDent_;
  double beforeLiftOff_ = 0.0;
  Frame::Phase previousPhase_ = Frame::Press;
  int restFrames_ = 0;
};

}  // namespace live_stream
