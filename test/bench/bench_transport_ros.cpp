// In->out latency of the enrichment node for 10k and 100k-vertex mesh states, as a nodelet (same process,
// shared pointers) and as a separate process, next to the floor: a bare relay that republishes the same
// PointCloud2 over the same transport, measured in the same run. Needs a running master (scripts/bench).
// Usage: bench_transport_ros [--samples N]   (internal: --relay, run as the separate relay process)
#include <nodelet/loader.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <unistd.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace de = deformation_enrichment;

namespace {

std::string selfDirectory() {
  char path[4096];
  const ssize_t length = readlink("/proc/self/exe", path, sizeof(path) - 1);
  std::string exe(path, length > 0 ? static_cast<size_t>(length) : 0);
  return exe.substr(0, exe.find_last_of('/'));
}

pid_t spawn(const std::vector<std::string>& argv) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

int runRelay() {  // republishes the received pointer unchanged: transport only
  ros::NodeHandle nh;
  ros::Publisher out = nh.advertise<sensor_msgs::PointCloud2>("out", 2);
  ros::Subscriber in = nh.subscribe<sensor_msgs::PointCloud2>("in", 2, [&](const sensor_msgs::PointCloud2ConstPtr& m) { out.publish(m); });
  ros::spin();
  return 0;
}

struct Percentiles {
  double p50, p90, p99;
  size_t received;
};

// Ping-pong: publish one state, wait for the message with its stamp on `outTopic`, repeat.
Percentiles measure(ros::NodeHandle& nh, const std::string& inTopic, const std::string& outTopic,
                    const de::mesh::TriangleMesh& rest, int samples) {
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>(inTopic, 2);
  std::atomic<int64_t> lastStamp{-1};
  std::vector<double> latencies;
  ros::Subscriber sub = nh.subscribe<sensor_msgs::PointCloud2>(outTopic, 2, [&](const sensor_msgs::PointCloud2ConstPtr& m) {
    latencies.push_back((ros::WallTime::now().toSec() - m->header.stamp.toSec()) * 1e3);
    lastStamp = static_cast<int64_t>(m->header.stamp.toNSec());
  });
  const ros::WallTime connectDeadline = ros::WallTime::now() + ros::WallDuration(20.0);
  while ((pub.getNumSubscribers() == 0 || sub.getNumPublishers() == 0) && ros::WallTime::now() < connectDeadline) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  std_msgs::Header header;
  header.frame_id = "bench";
  const Eigen::Matrix3Xf positions = rest.vertices.cast<float>();
  for (int i = -20; i < samples; ++i) {  // 20 warm-up rounds (connections, rest mesh arrival, caches)
    if (i == 0) latencies.clear();
    auto cloud = boost::make_shared<sensor_msgs::PointCloud2>(de::ros_layer::cloudFromPositions(positions, header));
    const ros::WallTime now = ros::WallTime::now();
    cloud->header.stamp = ros::Time(now.sec, now.nsec);
    const int64_t stamp = static_cast<int64_t>(cloud->header.stamp.toNSec());
    pub.publish(sensor_msgs::PointCloud2ConstPtr(cloud));
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(1.0);
    while (lastStamp != stamp && ros::WallTime::now() < deadline) ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.0001));
  }
  std::sort(latencies.begin(), latencies.end());
  auto at = [&](double p) { return latencies.empty() ? -1.0 : latencies[std::min(latencies.size() - 1, size_t(p * latencies.size()))]; };
  return {at(0.5), at(0.9), at(0.99), latencies.size()};
}

void report(const char* label, size_t vertices, const Percentiles& node, const Percentiles& floor) {
  std::printf("%-8s %7zu  enrichment p50 %8.3f p90 %8.3f p99 %8.3f ms (%3zu)  | floor p50 %8.3f p90 %8.3f p99 %8.3f ms (%3zu)"
              "  | p99 over floor %+.3f ms\n",
              label, vertices, node.p50, node.p90, node.p99, node.received, floor.p50, floor.p90, floor.p99, floor.received,
              node.p99 - floor.p99);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_transport", ros::init_options::AnonymousName);
  int samples = 200;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--relay") return runRelay();
    if (std::string(argv[i]) == "--samples" && i + 1 < argc) samples = std::stoi(argv[++i]);
  }
  ros::NodeHandle nh;
  const std::string dir = selfDirectory();
  std::printf("mode     vertices  in->out latency of mesh_state -> enriched_mesh_state vs a bare relay (same transport)\n");
  for (const int cells : {70, 223}) {  // ~10k and ~100k surface vertices
    const de::mesh::TriangleMesh rest = de::mesh::extractSurface(de::mesh::gridTetMesh(
        Eigen::Vector3d(-0.05, -0.05, 0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(cells, cells, 1))).surface;
    const std::string ns = "/bench" + std::to_string(cells);
    ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>(ns + "/rest_mesh", 1, true);
    std_msgs::Header header;
    header.frame_id = "bench";
    restPub.publish(de::ros_layer::messageFromTriangleMesh(rest, header));

    // Nodelet: the enrichment and the relay live in this process and share pointers with it.
    nodelet::Loader loader(false);
    nodelet::M_string remap{{"mesh_state", ns + "/nodelet/in"}, {"enriched_mesh_state", ns + "/nodelet/out"},
                            {"rest_mesh", ns + "/rest_mesh"}};
    loader.load(ns + "/enrichment_nodelet", "deformation_enrichment/EnrichmentNodelet", remap, {});
    ros::Publisher relayOut = nh.advertise<sensor_msgs::PointCloud2>(ns + "/nodelet_relay/out", 2);
    ros::Subscriber relayIn = nh.subscribe<sensor_msgs::PointCloud2>(
        ns + "/nodelet_relay/in", 2, [&](const sensor_msgs::PointCloud2ConstPtr& m) { relayOut.publish(m); });
    const Percentiles nodeletNode = measure(nh, ns + "/nodelet/in", ns + "/nodelet/out", rest, samples);
    const Percentiles nodeletFloor = measure(nh, ns + "/nodelet_relay/in", ns + "/nodelet_relay/out", rest, samples);
    report("nodelet", static_cast<size_t>(rest.numVertices()), nodeletNode, nodeletFloor);
    loader.clear();

    // Separate processes: enrichment_node and a relay process, both serialising over TCPROS.
    const pid_t node = spawn({dir + "/enrichment_node", "mesh_state:=" + ns + "/proc/in",
                              "enriched_mesh_state:=" + ns + "/proc/out", "rest_mesh:=" + ns + "/rest_mesh",
                              "__name:=bench_enrichment" + std::to_string(cells)});
    const pid_t relay = spawn({dir + "/bench_transport_ros", "--relay", "in:=" + ns + "/proc_relay/in",
                               "out:=" + ns + "/proc_relay/out", "__name:=bench_relay" + std::to_string(cells)});
    const Percentiles processNode = measure(nh, ns + "/proc/in", ns + "/proc/out", rest, samples);
    const Percentiles processFloor = measure(nh, ns + "/proc_relay/in", ns + "/proc_relay/out", rest, samples);
    report("process", static_cast<size_t>(rest.numVertices()), processNode, processFloor);
    for (const pid_t pid : {node, relay}) {
      kill(pid, SIGINT);
      waitpid(pid, nullptr, 0);
    }
  }
  return 0;
}
