// The enrichment node's configuration at run time: the rest surface at start-up (~scene, ~rest_mesh_file),
// example sets and the dynamically reconfigurable knobs. Slow work (building an enricher) runs in the session, outside the frame path.
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/ros/enrichment_node.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

namespace deformation_enrichment::ros_layer {

std::optional<enrichment::RestGeometry> EnrichmentNode::startupRest() {
  if (!parameters_.scene.empty()) {
    try {
      const scene_file::SceneDescription scene = scene_file::readSceneFile(scene_file::findSceneFile(parameters_.scene));
      scenes::SceneGeometry geometry = scenes::sceneGeometry(scene);
      if (!parameters_.maxOutside) parameters_.session.density.maxOutside = scene.maxOutside;
      sceneVolume_ = geometry.volume;
      parameters_.session.scene = scene;
      ROS_INFO("scene '%s': %s", parameters_.scene.c_str(), geometry.report.c_str());
      return enrichment::RestGeometry{std::move(geometry.surface), std::move(geometry.volume), "scene " + scene.name};
    } catch (const Error& e) {
      ROS_ERROR("~scene '%s' rejected: %s (using ~rest_mesh_file or the rest_mesh topic instead)", parameters_.scene.c_str(),
                e.what());
    }
  }
  if (parameters_.maxOutside) parameters_.session.density.maxOutside = *parameters_.maxOutside;
  if (parameters_.restMeshFile.empty()) return std::nullopt;
  try {
    return enrichment::RestGeometry{mesh::readTriangleMesh(parameters_.restMeshFile), std::nullopt,
                                    "file " + parameters_.restMeshFile};
  } catch (const Error& e) {
    ROS_ERROR("rest mesh file rejected: %s (waiting for the rest_mesh topic instead)", e.what());
    return std::nullopt;
  }
}

void EnrichmentNode::loadExampleSet(const std::string& path) {
  // One configuration change at a time (reconfigure callbacks hold this mutex too).
  boost::recursive_mutex::scoped_lock configLock(reconfigureMutex_);
  examples::ExampleSet set = examples::loadExampleSet(path);
  if (set.examples.empty()) throw InvalidInputError("example set '" + path + "' has no examples");
  const std::size_t count = set.examples.size();
  session_->setExampleSet(std::move(set));
  ROS_INFO("example set '%s' active: %zu examples, Hermite order %d", path.c_str(), count, session_->diagnostics().hermiteOrder);
}

bool EnrichmentNode::onLoadExampleSet(LoadExampleSet::Request& request, LoadExampleSet::Response& response) {
  try {
    loadExampleSet(request.path);
    response.success = true;
    response.num_examples = static_cast<uint32_t>(session_->exampleCount());
    response.message = "loaded " + std::to_string(response.num_examples) + " examples";
  } catch (const Error& e) {
    response.success = false;
    response.message = e.what();
    response.num_examples = static_cast<uint32_t>(session_->exampleCount());
    ROS_ERROR("load_example_set '%s' rejected, the previous set stays active: %s", request.path.c_str(), e.what());
  }
  return true;
}

void EnrichmentNode::onReconfigure(EnrichmentConfig& config, uint32_t /*level*/) {
  const enrichment::KnobOptions kept = session_->knobs();
  enrichment::KnobOptions requested = kept;
  requested.gain.stampGain = config.stamp_gain;
  requested.sigmaRho = config.sigma_rho;
  requested.sigmaU = config.sigma_u;
  requested.hermiteOrder = config.hermite_order;
  requested.gain.minConfidence = config.min_confidence;
  requested.gain.maxWeightNorm = config.max_weight_norm;
  requested.temporalSmoothing = config.temporal_smoothing;
  try {
    requested.blend = enrichment::parseBlendMethod(config.blend);
  } catch (const Error& e) {
    ROS_ERROR("%s: keeping blend %s", e.what(), enrichment::toString(kept.blend));
  }
  // Whatever is refused, the reply (and rqt_reconfigure) shows the values in use.
  try {
    session_->setKnobs(requested);
  } catch (const Error& e) {
    if (requested.hermiteOrder == kept.hermiteOrder) {
      ROS_ERROR("reconfiguration refused: %s (keeping stamp_gain %g, sigma_rho %g, sigma_u %g, min_confidence %g, "
                "max_weight_norm %g, temporal_smoothing %g)", e.what(), kept.gain.stampGain, kept.sigmaRho, kept.sigmaU,
                kept.gain.minConfidence, kept.gain.maxWeightNorm, kept.temporalSmoothing);
      requested = kept;
    } else {  // the order alone is refused (above the active set's): the other knobs still apply
      ROS_ERROR("hermite_order %d refused: %s (keeping hermite_order %d)", requested.hermiteOrder, e.what(), kept.hermiteOrder);
      requested.hermiteOrder = kept.hermiteOrder;
      try {
        session_->setKnobs(requested);
      } catch (const Error& again) {
        ROS_ERROR("reconfiguration refused: %s (keeping the previous values)", again.what());
        requested = kept;
      }
    }
  }
  config.stamp_gain = requested.gain.stampGain;
  config.sigma_rho = requested.sigmaRho;
  config.sigma_u = requested.sigmaU;
  config.hermite_order = requested.hermiteOrder;
  config.min_confidence = requested.gain.minConfidence;
  config.max_weight_norm = requested.gain.maxWeightNorm;
  config.temporal_smoothing = requested.temporalSmoothing;
  config.blend = enrichment::toString(requested.blend);
}

}  // namespace deformation_enrichment::ros_layer
