// A live stream that holds still (docs/accuracy.md), measured on the run-time pipeline the node uses: the scenario
// and measures of live_stream_scenario.hpp, per (spacing, speed), against their bounds.
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
#include "live_stream_scenario.hpp"

using namespace deformation_enrichment;

namespace {
using namespace live_stream;

Measures run(const examples::ExampleSet& set, double spacing, double speed, double smoothing) {
  const mesh::TriangleMesh box = boxSurface(spacing);
  enrichment::ContactEnricher enricher(box, enrichment::optionsFor(set));
  enricher.setExamples(set);
  enrichment::ContactContinuity continuity;
  enrichment::TemporalFilter filter(smoothing);
  const Eigen::Matrix3Xd& rest = box.vertices;
  StreamMeter meter(rest.cols());
  enrichment::EnrichmentResult result;
  for (const Frame& f : sequence(speed)) {
    const Eigen::Matrix3Xd coarse = coarseState(rest, f);
    std::vector<enrichment::Contact> touching;
    if (f.touching) {
      enrichment::Contact c;
      c.point = toolPoint(f);
      c.restState = false;
      touching.push_back(c);
    }
    enricher.enrich(coarse, continuity.contactsFor(touching), result);
    continuity.update(result);
    filter.filter(result.enrichment, kFramePeriod, rest.cols());
    Eigen::Matrix3Xd enriched = coarse;
    enricher.apply(result, enriched);
    if (!enriched.allFinite()) throw NumericalError("live stream check: a non-finite enriched state");
    meter.add(f, enriched - coarse, coarse - rest);
  }
  return meter.measures();
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
  double maxFlicker = kMaxFlicker, minRetained = kMinRetained, maxResidual = kMaxResidual, smoothing = 0.0;
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
        const bool pass = m.withinBounds(maxFlicker, minRetained, maxResidual);
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
