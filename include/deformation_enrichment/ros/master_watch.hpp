#pragma once
// Watches the ROS master a node registered with. roscpp never registers a node's topics and services again
// with a master that restarted, so such a node would run on, deaf. The watch asks the master, on its own
// thread, whether it still knows this node; when a master answers that does not, it writes the node's
// private parameters (as last read from the old master) to the new one, says why on the log, and requests
// shutdown, so that a launch file's respawn="true" starts the node again, registered and configured.
#include <ros/callback_queue.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <memory>
#include <string>

namespace deformation_enrichment::ros_layer {

class MasterWatch {
public:
  /// Checks every `period` seconds (0: never). `privateNh` names the parameters to carry over.
  MasterWatch(const ros::NodeHandle& privateNh, double period);
  ~MasterWatch();

private:
  void check();

  std::string parameterNamespace_;
  XmlRpc::XmlRpcValue parameters_;  // the private namespace as the master held it at the last check
  bool unreachable_ = false;
  ros::CallbackQueue queue_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  ros::WallTimer timer_;
};

}  // namespace deformation_enrichment::ros_layer
