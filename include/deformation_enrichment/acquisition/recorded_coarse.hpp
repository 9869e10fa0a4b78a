#pragma once
// The coarse half of examples recorded from another simulator (docs/coarse_simulator.md): the display-surface
// state it settled in at the end of each plan interaction, as acquisition_driver records them in a bag.
// Acquisition and held-out evaluation take the coarse state from here instead of solving their own coarse
// model, so stamps encode fine minus the coarse model that runs live [Seiler14 §3].
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "deformation_enrichment/acquisition/plan_io.hpp"

namespace deformation_enrichment::acquisition {

struct RecordedCoarse {
  std::string path;       ///< the recording (a bag), hashed into the set's provenance
  std::string simulator;  ///< the simulator as it announced itself
  std::vector<PlanEntry> plan;                       ///< the plan the recording was driven by
  std::map<std::size_t, Eigen::Matrix3Xd> settled;   ///< plan line (0-based) -> settled display-surface state
};

}  // namespace deformation_enrichment::acquisition
