// Nodelet form of the enrichment node: same class, shared pointers between nodelets (zero copy).
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

#include "deformation_enrichment/ros/enrichment_node.hpp"

namespace deformation_enrichment::ros_layer {

class EnrichmentNodelet : public nodelet::Nodelet {
private:
  void onInit() override { node_ = std::make_unique<EnrichmentNode>(getMTNodeHandle(), getMTPrivateNodeHandle()); }
  std::unique_ptr<EnrichmentNode> node_;
};

}  // namespace deformation_enrichment::ros_layer

PLUGINLIB_EXPORT_CLASS(deformation_enrichment::ros_layer::EnrichmentNodelet, nodelet::Nodelet)
