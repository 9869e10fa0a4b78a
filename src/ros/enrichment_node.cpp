// Standalone process form of the enrichment node (see EnrichmentNodelet for the in-process form).
#include "deformation_enrichment/ros/enrichment_node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "enrichment_node");
  deformation_enrichment::ros_layer::EnrichmentNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  ros::spin();
  return 0;
}
