// The enrichment node's configuration at run time: example sets, the dynamically reconfigurable knobs
// (stamp gain, kernel widths, Hermite order), the tool pose topics and their tips' geometry from
// robot_description.
// Slow work (building an enricher: interior sampling, leave-one-out width fit) runs on the service thread
// outside the frame lock; the finished enricher is swapped in under it, so a change applies from the next
// mesh state on.
#include <algorithm>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/ros/enrichment_node.hpp"

namespace deformation_enrichment::ros_layer {

std::unique_ptr<enrichment::ContactEnricher> EnrichmentNode::makeEnricher(const mesh::TriangleMesh& rest,
                                                                          const examples::ExampleSet& set,
                                                                          const EnrichmentKnobs& knobs) const {
  // Contacts are described exactly as the set's examples were (window, quadrature, interior sampling,
  // orders, stamp radius); ~descriptor_scale and ~segmentation_sample_spacing only fill in what a set
  // does not record. A lower mu order may be chosen by knob.
  enrichment::ContactEnricherOptions defaults;
  defaults.descriptors.window.scale = segmentation_.scale;
  defaults.sampleSpacing = segmentation_.sampleSpacing;
  enrichment::ContactEnricherOptions options = enrichment::optionsFor(set, defaults);
  const int built = options.descriptors.deformationOrder;
  const int order = knobs.hermiteOrder > 0 ? std::min(knobs.hermiteOrder, built) : built;
  options.descriptors.deformationOrder = order;
  options.stampGain = knobs.stampGain;
  options.minConfidence = knobs.minConfidence;
  auto enricher = std::make_unique<enrichment::ContactEnricher>(rest, options);
  // Truncated mu: the leave-one-out widths are fitted for the descriptors actually compared.
  enricher->setExamples(enrichment::withDeformationOrder(set, order));
  enricher->setKernelWidths(knobs.sigmaRho, knobs.sigmaU);
  return enricher;
}

void EnrichmentNode::installEnricher(examples::ExampleSet set, const EnrichmentKnobs& knobs) {
  std::optional<mesh::TriangleMesh> rest;
  uint64_t restVersion = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    rest = rest_;
    restVersion = restVersion_;
  }
  // Built outside the lock (interior sampling, kernel-width fitting): the enrichment goes on meanwhile.
  std::unique_ptr<enrichment::ContactEnricher> enricher = rest ? makeEnricher(*rest, set, knobs) : nullptr;
  std::lock_guard<std::mutex> lock(mutex_);
  if (restVersion_ != restVersion) enricher = rest_ ? makeEnricher(*rest_, set, knobs) : nullptr;  // rest changed meanwhile
  exampleSet_ = std::move(set);
  enricher_ = std::move(enricher);
  knobs_ = knobs;
  ++configVersion_;
}

void EnrichmentNode::loadExampleSet(const std::string& path) {
  // One configuration change at a time (reconfigure callbacks hold this mutex too).
  boost::recursive_mutex::scoped_lock configLock(reconfigureMutex_);
  examples::ExampleSet set = examples::loadExampleSet(path);
  if (set.examples.empty()) throw InvalidInputError("example set '" + path + "' has no examples");
  const int built = enrichment::deformationOrder(set);
  EnrichmentKnobs knobs;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    knobs = knobs_;
  }
  if (knobs.hermiteOrder > built)
    ROS_WARN("example set '%s' stores deformation moments up to order %d: hermite_order %d runs at %d", path.c_str(),
             built, knobs.hermiteOrder, built);
  installEnricher(std::move(set), knobs);
  ROS_INFO("example set '%s' active: %zu examples, Hermite order %d", path.c_str(), exampleSet_->examples.size(),
           std::min(built, knobs.hermiteOrder > 0 ? knobs.hermiteOrder : built));
}

bool EnrichmentNode::onLoadExampleSet(LoadExampleSet::Request& request, LoadExampleSet::Response& response) {
  try {
    loadExampleSet(request.path);
    std::lock_guard<std::mutex> lock(mutex_);
    response.success = true;
    response.num_examples = static_cast<uint32_t>(exampleSet_->examples.size());
    response.message = "loaded " + std::to_string(response.num_examples) + " examples";
  } catch (const Error& e) {
    response.success = false;
    response.message = e.what();
    std::lock_guard<std::mutex> lock(mutex_);
    response.num_examples = exampleSet_ ? static_cast<uint32_t>(exampleSet_->examples.size()) : 0;
    ROS_ERROR("load_example_set '%s' rejected, the previous set stays active: %s", request.path.c_str(), e.what());
  }
  return true;
}

void EnrichmentNode::onReconfigure(EnrichmentConfig& config, uint32_t /*level*/) {
  EnrichmentKnobs requested{config.stamp_gain,     config.sigma_rho,       config.sigma_u,
                            config.hermite_order,  config.min_confidence,  config.temporal_smoothing};
  EnrichmentKnobs old;
  std::optional<examples::ExampleSet> set;
  int activeOrder = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    old = knobs_;
    set = exampleSet_;  // stamps are shared cv::Mat headers: cheap
    if (enricher_) activeOrder = enricher_->options().descriptors.deformationOrder;
  }
  if (set) {
    const int built = enrichment::deformationOrder(*set);
    if (requested.hermiteOrder > built) {
      ROS_ERROR("hermite_order %d refused: the active example set stores deformation moments up to order %d only "
                "(keeping hermite_order %d)", requested.hermiteOrder, built, old.hermiteOrder);
      requested.hermiteOrder = old.hermiteOrder;
      config.hermite_order = old.hermiteOrder;
    }
    const int order = requested.hermiteOrder > 0 ? requested.hermiteOrder : built;
    if (activeOrder != 0 && order != activeOrder) {
      try {  // new descriptors on both sides: a new enricher, widths fitted again for them
        installEnricher(std::move(*set), requested);
        ROS_INFO("Hermite order of the deformation descriptor now %d (set built with %d)", order, built);
      } catch (const Error& e) {
        ROS_ERROR("hermite_order %d refused: %s (keeping hermite_order %d)", requested.hermiteOrder, e.what(),
                  old.hermiteOrder);
        requested.hermiteOrder = old.hermiteOrder;
        config.hermite_order = old.hermiteOrder;
      }
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    if (enricher_) {
      enricher_->setStampGain(requested.stampGain);
      enricher_->setKernelWidths(requested.sigmaRho, requested.sigmaU);  // O(N^3) in the examples: cheap
      enricher_->setMinConfidence(requested.minConfidence);
    }
    if (requested.temporalSmoothing != temporalFilter_.timeConstant()) temporalFilter_.setTimeConstant(requested.temporalSmoothing);
    knobs_ = requested;
  } catch (const Error& e) {
    ROS_ERROR("reconfiguration refused: %s (keeping stamp_gain %g, sigma_rho %g, sigma_u %g)", e.what(), old.stampGain,
              old.sigmaRho, old.sigmaU);
    if (enricher_) {
      enricher_->setStampGain(old.stampGain);
      enricher_->setKernelWidths(old.sigmaRho, old.sigmaU);
      enricher_->setMinConfidence(old.minConfidence);
    }
    knobs_.minConfidence = old.minConfidence;
    config.min_confidence = old.minConfidence;
    knobs_.stampGain = old.stampGain;
    knobs_.sigmaRho = old.sigmaRho;
    knobs_.sigmaU = old.sigmaU;
    config.stamp_gain = old.stampGain;
    config.sigma_rho = old.sigmaRho;
    config.sigma_u = old.sigmaU;
  }
  ++configVersion_;  // the next state is computed afresh
}

ToolTip EnrichmentNode::loadToolTip(const std::string& link, std::string& status) const {
  if (link.empty()) {
    status = ToolTip().description();
    return {};
  }
  std::string key, urdf;
  if (!privateNh_.searchParam("robot_description", key) || !privateNh_.getParam(key, urdf)) {
    status = "point (no robot_description for tip link '" + link + "')";
    ROS_WARN("tip link '%s' is set but there is no robot_description: the tool pose position is the tip", link.c_str());
    return {};
  }
  try {
    ToolTip tip = toolTipFromUrdf(urdf, link);
    status = tip.description();
    ROS_INFO("tool tip: %s", status.c_str());
    return tip;
  } catch (const Error& e) {
    status = std::string("point (robot_description rejected: ") + e.what() + ")";
    ROS_ERROR("tool tip from robot_description rejected: %s; the tool pose position is the tip", e.what());
    return {};
  }
}

void EnrichmentNode::subscribeToolPoses() {
  std::vector<ToolPoseSpec> specs = defaultToolPoseSpecs(privateNh_.param<std::string>("tool_pose_id", "tool_pose"),
                                                         privateNh_.param<std::string>("tool_tip_link", ""));
  XmlRpc::XmlRpcValue list;
  if (privateNh_.getParam("tool_poses", list)) {
    try {
      std::vector<ToolPoseSpec> listed = toolPoseSpecs(list);
      if (!listed.empty()) specs = std::move(listed);
    } catch (const Error& e) {
      ROS_ERROR("%s: subscribing tool_pose and tool_transform instead", e.what());
    }
  }
  for (const ToolPoseSpec& spec : specs) {
    auto source = std::make_unique<ToolPoseSource>();
    source->spec = spec;
    source->tip = loadToolTip(spec.tipLink, source->tipStatus);
    const ToolPoseSource* self = source.get();
    if (spec.type == ToolPoseSpec::Type::Pose) {
      source->subscriber = nh_.subscribe<geometry_msgs::PoseStamped>(
          spec.topic, 10, [this, self](const geometry_msgs::PoseStampedConstPtr& message) { updateToolPose(*message, *self); });
    } else {
      source->subscriber = nh_.subscribe<geometry_msgs::TransformStamped>(
          spec.topic, 10, [this, self](const geometry_msgs::TransformStampedConstPtr& message) {
            geometry_msgs::PoseStamped pose;
            pose.header = message->header;  // the transform's parent frame is the pose's frame
            pose.pose.position.x = message->transform.translation.x;
            pose.pose.position.y = message->transform.translation.y;
            pose.pose.position.z = message->transform.translation.z;
            pose.pose.orientation = message->transform.rotation;
            updateToolPose(pose, *self);
          });
    }
    ROS_INFO("tool '%s' from %s (%s)", spec.id.c_str(), source->subscriber.getTopic().c_str(),
             spec.type == ToolPoseSpec::Type::Pose ? "geometry_msgs/PoseStamped" : "geometry_msgs/TransformStamped");
    toolSources_.push_back(std::move(source));
  }
}

}  // namespace deformation_enrichment::ros_layer
