// A live stream that holds still (issue 13), measured on the run-time pipeline the node uses: a closed box
// surface of the slab's size, meshed at a given vertex spacing, carries a coarse dent (Gaussian, 3 mm deep)
// that is pressed, slid along x at a given speed per frame, held, released by the tool while the tissue is
// still dented, then relaxed back to rest. Every frame is enriched with the default slab example set.
// Printed per (spacing, speed):
//   flicker   max over the slide and hold frames of |d_t - d_t-1| / max(|d_t|, |d_t-1|) for the added detail
//             d, divided by the same measure of the coarse dent c = coarse - rest (bound: --max-flicker);
//   retained  |d| on the first frame after lift-off over |d| on the frame before (bound: --min-retained);
//   residual  the largest |d| from the third frame back at rest on, over |d| before lift-off (--max-residual).
// Frames come at 60 Hz; --temporal-smoothing TAU (seconds, default 0 = off) filters the added field.
// Usage: live_stream_check SET_DIR [--spacings mm,...] [--speeds mm,...] [--max-flicker X] [--min-retained X]
//        [--max-residual X] [--temporal-smoothing TAU]. Exits 1 when a bound is missed.
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/contact_continuity.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/temporal_filter.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {

constexpr double kTop = 0.02, kDepth = 0.003, kSigma = 0.006, kSlide = 0.008, kFramePeriod = 1.0 / 60.0;

struct Frame {
  double x = 0.0, depth = 0.0;
  bool touching = false;
  enum Phase { Press, Slide, Hold, Lifted, Relax, Rest } phase = Press;
};

std::vector<Frame> sequence(double speed) {
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

// The coarse state: a smooth dent under (x, 0, top), fading with depth into the slab.
Eigen::Matrix3Xd coarseState(const Eigen::Matrix3Xd& rest, const Frame& f) {
  Eigen::Matrix3Xd x = rest;
  const Eigen::Vector3d centre(f.x, 0.0, kTop);
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    x(2, v) -= f.depth * std::exp(-(rest.col(v) - centre).squaredNorm() / (2 * kSigma * kSigma)) * rest(2, v) / kTop;
  return x;
}

double relativeChange(const Eigen::Matrix3Xd& now, const Eigen::Matrix3Xd& before) {
  const double size = std::max(now.norm(), before.norm());
  return size > 0.0 ? (now - before).norm() / size : 0.0;
}

struct Measures {
  double detailFlicker = 0.0, coarseFlicker = 0.0, retained = 0.0, residual = 0.0;
  double flickerRatio() const { return coarseFlicker > 0.0 ? detailFlicker / coarseFlicker : 0.0; }
};

Measures run(const examples::ExampleSet& set, double spacing, double speed, double smoothing) {
  const auto cells = [&](double length) { return std::max(1, static_cast<int>(std::lround(length / spacing))); };
  const mesh::TetSurface box = mesh::extractSurface(mesh::gridTetMesh(
      Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, kTop), Eigen::Vector3i(cells(0.1), cells(0.1), cells(kTop))));
  enrichment::ContactEnricher enricher(box.surface, enrichment::optionsFor(set));
  enricher.setExamples(set);
  enrichment::ContactContinuity continuity;
  enrichment::TemporalFilter filter(smoothing);
  const Eigen::Matrix3Xd& rest = box.surface.vertices;

  Measures m;
  Eigen::Matrix3Xd previousDetail = Eigen::Matrix3Xd::Zero(3, rest.cols()), previousDent = previousDetail;
  double beforeLiftOff = 0.0;
  Frame::Phase previousPhase = Frame::Press;
  int restFrames = 0;
  enrichment::EnrichmentResult result;
  for (const Frame& f : sequence(speed)) {
    const Eigen::Matrix3Xd coarse = coarseState(rest, f);
    std::vector<enrichment::Contact> touching;
    if (f.touching) {
      enrichment::Contact c;
      c.point = Eigen::Vector3d(f.x, 0.0, kTop - f.depth);  // where the tool is: on the dented surface
      c.restState = false;
      touching.push_back(c);
    }
    enricher.enrich(coarse, continuity.contactsFor(touching), result);
    continuity.update(result);
    filter.filter(result.enrichment, kFramePeriod, rest.cols());
    Eigen::Matrix3Xd enriched = coarse;
    enricher.apply(result, enriched);
    const Eigen::Matrix3Xd detail = enriched - coarse, dent = coarse - rest;
    if (f.phase == Frame::Slide || f.phase == Frame::Hold) {
      m.detailFlicker = std::max(m.detailFlicker, relativeChange(detail, previousDetail));
      m.coarseFlicker = std::max(m.coarseFlicker, relativeChange(dent, previousDent));
    }
    if (f.phase == Frame::Lifted && previousPhase == Frame::Hold) {
      beforeLiftOff = previousDetail.norm();
      m.retained = beforeLiftOff > 0.0 ? detail.norm() / beforeLiftOff : 0.0;
    }
    if (f.phase == Frame::Rest && ++restFrames >= 3 && beforeLiftOff > 0.0)
      m.residual = std::max(m.residual, detail.norm() / beforeLiftOff);
    if (!enriched.allFinite()) throw NumericalError("live stream check: a non-finite enriched state");
    previousDetail = detail;
    previousDent = dent;
    previousPhase = f.phase;
  }
  return m;
}

std::vector<double> millimetres(const std::string& list) {
  std::vector<double> values;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) values.push_back(std::stod(item) * 1e-3);
  return values;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: live_stream_check SET_DIR [--spacings mm,...] [--speeds mm,...] [--max-flicker X] "
                         "[--min-retained X] [--max-residual X] [--temporal-smoothing TAU]\n");
    return 1;
  }
  std::vector<double> spacings = {0.001, 0.0025, 0.005}, speeds = {0.0001, 0.00025, 0.001};
  double maxFlicker = 3.0, minRetained = 0.5, maxResidual = 0.05, smoothing = 0.0;
  for (int a = 2; a + 1 < argc; a += 2) {
    const std::string key = argv[a], value = argv[a + 1];
    if (key == "--spacings") spacings = millimetres(value);
    else if (key == "--speeds") speeds = millimetres(value);
    else if (key == "--max-flicker") maxFlicker = std::stod(value);
    else if (key == "--min-retained") minRetained = std::stod(value);
    else if (key == "--max-residual") maxResidual = std::stod(value);
    else if (key == "--temporal-smoothing") smoothing = std::stod(value);
    else {
      std::fprintf(stderr, "live_stream_check: unknown option %s\n", key.c_str());
      return 1;
    }
  }
  try {
    const examples::ExampleSet set = examples::loadExampleSet(argv[1]);
    bool ok = true;
    std::printf("spacing_mm speed_mm  detail_flicker coarse_flicker ratio  retained residual\n");
    for (double spacing : spacings)
      for (double speed : speeds) {
        const Measures m = run(set, spacing, speed, smoothing);
        const bool pass = m.flickerRatio() <= maxFlicker && m.retained >= minRetained && m.residual <= maxResidual;
        ok = ok && pass;
        std::printf("%10.2f %8.2f  %14.4f %14.4f %6.2f %9.3f %8.4f %s\n", spacing * 1e3, speed * 1e3, m.detailFlicker,
                    m.coarseFlicker, m.flickerRatio(), m.retained, m.residual, pass ? "ok" : "FAIL");
        std::fflush(stdout);
      }
    std::printf("bounds: ratio <= %.2f, retained >= %.2f, residual <= %.3f\n", maxFlicker, minRetained, maxResidual);
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "live_stream_check: %s\n", e.what());
    return 1;
  }
}
