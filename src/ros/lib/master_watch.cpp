#include "deformation_enrichment/ros/master_watch.hpp"

#include <ros/master.h>
#include <ros/param.h>
#include <ros/this_node.h>

namespace deformation_enrichment::ros_layer {

MasterWatch::MasterWatch(const ros::NodeHandle& privateNh, double period) : parameterNamespace_(privateNh.getNamespace()) {
  if (!(period > 0.0)) return;
  ros::param::get(parameterNamespace_, parameters_);
  ros::NodeHandle nh(privateNh);
  nh.setCallbackQueue(&queue_);  // a master that hangs delays only this thread
  timer_ = nh.createWallTimer(ros::WallDuration(period), [this](const ros::WallTimerEvent&) { check(); });
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

MasterWatch::~MasterWatch() {
  timer_.stop();
  if (spinner_) spinner_->stop();
}

void MasterWatch::check() {
  if (!ros::master::check()) {
    if (!unreachable_)
      ROS_WARN("the ROS master at %s does not answer; the node goes on with what still arrives and waits for it",
               ros::master::getURI().c_str());
    unreachable_ = true;
    return;
  }
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  request[1] = ros::this_node::getName();
  if (ros::master::execute("lookupNode", request, response, payload, false)) {
    if (unreachable_) ROS_INFO("the ROS master at %s answers again", ros::master::getURI().c_str());
    unreachable_ = false;
    XmlRpc::XmlRpcValue current;
    if (ros::param::get(parameterNamespace_, current)) parameters_ = current;
    return;
  }
  // Only the master's own answer "unknown node" (status -1) means it restarted; a call that failed on the
  // way is checked again next time.
  const bool unknownNode = response.valid() && response.getType() == XmlRpc::XmlRpcValue::TypeArray &&
                           response.size() > 0 && response[0].getType() == XmlRpc::XmlRpcValue::TypeInt &&
                           static_cast<int>(response[0]) == -1;
  if (!unknownNode) return;
  if (parameters_.valid()) ros::param::set(parameterNamespace_, parameters_);
  ROS_FATAL("the ROS master at %s does not know node %s: it restarted, and roscpp does not register a node's "
            "topics and services again. Shutting down, with the parameters of %s written back to the new master, "
            "so that the launch file's respawn=\"true\" starts the node again (launch/enrichment.launch has it).",
            ros::master::getURI().c_str(), ros::this_node::getName().c_str(), parameterNamespace_.c_str());
  timer_.stop();
  ros::requestShutdown();
}

}  // namespace deformation_enrichment::ros_layer
