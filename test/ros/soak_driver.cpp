// The soak of scripts/soak: a 100k-vertex slab surface (10 x 10 x 2 cm box) dented under tool A, which
// circles the top, with mesh states at ~state_rate (60 Hz) and both tools' poses at ~pose_rate (1 kHz); tool
// B presses beside it for 10 s of every 20 (it joins and leaves); the enrichment node's markers are
// subscribed all along. Over ~seconds it counts the states sent and the enriched states received (every one
// must come back), the latency of each (receipt time minus the state's stamp, its sending time), and samples
// the resident memory of the process ~process_name (enrichment_node) every second. 5 s in, it stops the node
// for 80 ms (SIGSTOP), a stall of the host that the node's input queue must ride out. It prints one JSON line
// and exits 0 when no state was lost, at least 90 % of the states got detail and some both tools', and the
// memory held flat: the median of the last minute within 2 % of the second minute's (runs under three
// minutes: the last quarter's at most 2 % above the second's, as the allocator may return a stall's buffers).
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <signal.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "deformation_enrichment/EnrichmentStatus.h"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace de = deformation_enrichment;

namespace {

constexpr double kDepth = 0.002, kWidth = 0.006;  // the dents' depth and Gaussian width (m)
constexpr double kTop = 0.02;
// The node is stopped once, kNodePauseAt s in, for kNodePause s: five states arrive meanwhile. Before the
// memory's first window, so that window holds the input queue at its fullest.
constexpr double kNodePauseAt = 5.0, kNodePause = 0.08;

// The process whose executable is named `name` (the first found), 0 when there is none.
int findProcess(const std::string& name) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string pid = entry.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string executable;
    std::getline(std::ifstream(entry.path() / "cmdline"), executable, '\0');
    if (std::filesystem::path(executable).filename() == name) return std::stoi(pid);
  }
  return 0;
}

// Resident memory of process `pid` in kB (VmRSS), 0 when it cannot be read.
long residentKb(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

// Where tool A is at time t (s): a 2 cm circle on the top, one turn in 8 s; tool B sits at (-2, -2) cm.
Eigen::Vector3d toolA(double t) { return {0.02 * std::cos(t * M_PI / 4.0), 0.02 * std::sin(t * M_PI / 4.0), kTop - kDepth}; }
const Eigen::Vector3d kToolB(-0.02, -0.02, kTop - kDepth);
bool toolBPresent(double t) { return std::fmod(t, 20.0) >= 10.0; }

void dent(const Eigen::Matrix3Xf& rest, const Eigen::Vector3d& at, Eigen::Matrix3Xf& positions) {
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const double r2 = (rest.col(v).head<2>().cast<double>() - at.head<2>()).squaredNorm();
    if (rest(2, v) > kTop - 1e-6 && r2 < 16.0 * kWidth * kWidth)
      positions(2, v) -= static_cast<float>(kDepth * std::exp(-r2 / (2.0 * kWidth * kWidth)));
  }
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// The median of v[from, to): a stall's transient buffers do not move it, a leak does.
double median(const std::vector<long>& v, std::size_t from, std::size_t to) {
  if (to <= from) return 0.0;
  using Offset = std::ptrdiff_t;
  return percentile(std::vector<double>(v.begin() + static_cast<Offset>(from), v.begin() + static_cast<Offset>(to)), 0.5);
}
// A fixed-rate schedule that never bursts: after a stall of the driver itself (the host did not run it), the
// slots it missed are skipped and counted, as ros::Rate does, instead of sent back to back.
struct Schedule {
  double period, next = 0.0;
  long missed = 0;
  bool due(double t) {
    if (t < next) return false;
    const double late = std::floor((t - next) / period);
    missed += static_cast<long>(late);
    next += (late + 1.0) * period;
    return true;
  }
};

// What the driver observes of the node's outputs, from the start of the measurement on.
struct Observed {
  ros::Time measureFrom;  // states stamped from then on are counted (zero: not yet)
  long received = 0, markers = 0;
  long withDetail = 0, withTwoTools = 0;  // states whose status shows stamps placed / both tools in contact
  long lostBeforeTheNode = 0;  // the node's own count (/diagnostics) of states that never reached its callback
  std::vector<double> latencyMs;
};

// Publishes the rest state until the node enriches the 100k-vertex surface (its rest surface is built in the
// background); false if it does not answer within 120 s.
bool waitForNode(ros::NodeHandle& nh, ros::Publisher& statePub, sensor_msgs::PointCloud2& cloud) {
  long warm = 0;
  ros::Subscriber warmSub = nh.subscribe<sensor_msgs::PointCloud2>("enriched_mesh_state", 1, [&](const auto&) { ++warm; });
  for (ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(120.0); ros::ok() && warm < 3; ros::WallDuration(0.1).sleep()) {
    if (ros::WallTime::now() > deadline) return false;
    cloud.header.stamp = ros::Time::now();
    statePub.publish(cloud);
    ros::spinOnce();
  }
  return true;
}

// What the driver did: the states it sent, the state slots it missed while it was not run itself, its
// longest pause between two turns of its loop, and the node's resident memory once a second.
struct Driven {
  long sent = 0, missed = 0;
  double longestPauseMs = 0.0;
  bool nodePaused = false;  // the node was stopped for kNodePause
  std::vector<long> memory;
};

// States at stateRate with tool A's dent (and tool B's while present), poses at poseRate, for `seconds`.
Driven drive(double seconds, double stateRate, double poseRate, const Eigen::Matrix3Xf& rest, sensor_msgs::PointCloud2& cloud,
             ros::Publisher& statePub, ros::Publisher& posePubA, ros::Publisher& posePubB, int pid) {
  std_msgs::Header header = cloud.header;
  Driven d;
  Eigen::Matrix3Xf positions = rest;
  const ros::WallTime start = ros::WallTime::now();
  Schedule states{1.0 / stateRate}, poses{1.0 / poseRate}, samples{1.0};
  double previous = 0.0;
  bool paused = false, resumed = false;
  for (double t = 0.0; ros::ok() && t < seconds; t = (ros::WallTime::now() - start).toSec()) {
    d.longestPauseMs = std::max(d.longestPauseMs, 1e3 * (t - previous));
    previous = t;
    if (poses.due(t)) {
      header.stamp = ros::Time::now();
      posePubA.publish(de::ros_layer::poseAt(toolA(t), header));
      if (toolBPresent(t)) posePubB.publish(de::ros_layer::poseAt(kToolB, header));
    }
    if (states.due(t)) {
      positions = rest;
      dent(rest, toolA(t), positions);
      if (toolBPresent(t)) dent(rest, kToolB, positions);
      cloud.header.stamp = ros::Time::now();
      de::ros_layer::writePositions(positions, cloud);
      statePub.publish(cloud);
      ++d.sent;
    }
    if (samples.due(t)) d.memory.push_back(residentKb(pid));
    if (pid != 0 && !paused && t >= kNodePauseAt) paused = kill(pid, SIGSTOP) == 0;  // the host stalls the node
    if (paused && !resumed && t >= kNodePauseAt + kNodePause) resumed = kill(pid, SIGCONT) == 0;
    ros::spinOnce();
    ros::WallDuration(2e-4).sleep();
  }
  if (paused && !resumed) kill(pid, SIGCONT);
  d.missed = states.missed;
  d.nodePaused = paused;
  return d;
}

// Prints the soak's JSON line; true if every state came back, the memory held flat (last minute within 2 % of
// the second; a short run's last quarter at most 2 % above its second) and detail was placed.
bool report(double seconds, Eigen::Index vertices, const Driven& d, const Observed& o) {
  const std::size_t n = d.memory.size();
  const bool minutes = seconds >= 180.0;
  const double early = minutes ? median(d.memory, 60, 120) : median(d.memory, n / 4, n / 2);
  const double late = minutes ? median(d.memory, n - 60, n) : median(d.memory, 3 * n / 4, n);
  const double growth = early > 0.0 ? late / early - 1.0 : 0.0;
  // A short run may also fall: after a stall the allocator may return the queue's megabyte buffers.
  const bool flat = minutes ? std::abs(growth) <= 0.02 : growth <= 0.02;
  const bool ok = o.received == d.sent && early > 0.0 && flat && o.withDetail >= d.sent * 9 / 10 && o.withTwoTools > 0;
  std::printf("soak: {\"seconds\": %.0f, \"vertices\": %ld, \"states_sent\": %ld, \"states_enriched\": %ld, \"lost\": %ld, "
              "\"lost_before_the_node\": %ld, \"with_detail\": %ld, \"with_two_tools\": %ld, \"latency_ms\": {\"p50\": %.2f, \"p99\": %.2f, \"max\": %.2f}, "
              "\"marker_arrays\": %ld, \"resident_kb\": {\"early\": %.0f, \"late\": %.0f, \"growth\": %.4f}, "
              "\"driver\": {\"slots_missed\": %ld, \"longest_pause_ms\": %.1f}, \"node_paused_ms\": %.0f, \"ok\": %s}\n",
              seconds, static_cast<long>(vertices), d.sent, o.received, d.sent - o.received, o.lostBeforeTheNode, o.withDetail,
              o.withTwoTools, percentile(o.latencyMs, 0.5), percentile(o.latencyMs, 0.99), percentile(o.latencyMs, 1.0), o.markers, early, late,
              growth, d.missed, d.longestPauseMs, d.nodePaused ? 1e3 * kNodePause : 0.0, ok ? "true" : "false");
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "soak_driver");
  ros::NodeHandle nh, pnh("~");
  const double seconds = pnh.param("seconds", 60.0), stateRate = pnh.param("state_rate", 60.0), poseRate = pnh.param("pose_rate", 1000.0);
  const int cells = pnh.param("cells", 223);
  const std::string processName = pnh.param<std::string>("process_name", "enrichment_node");
  const de::mesh::TriangleMesh surface =
      de::mesh::extractSurface(de::mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0), Eigen::Vector3d(0.05, 0.05, kTop),
                                                     Eigen::Vector3i(cells, cells, 1)))
          .surface;
  const Eigen::Matrix3Xf rest = surface.vertices.cast<float>();
  std_msgs::Header header;
  header.frame_id = "slab";
  ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, true);
  ros::Publisher statePub = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 10);
  ros::Publisher posePubA = nh.advertise<geometry_msgs::PoseStamped>("PSM1/measured_cp", 100);
  ros::Publisher posePubB = nh.advertise<geometry_msgs::PoseStamped>("PSM2/measured_cp", 100);
  Observed o;
  ros::Subscriber enriched = nh.subscribe<sensor_msgs::PointCloud2>("enriched_mesh_state", 100, [&](const sensor_msgs::PointCloud2ConstPtr& m) {
    if (o.measureFrom.isZero() || m->header.stamp < o.measureFrom) return;
    ++o.received;
    o.latencyMs.push_back(1e3 * (ros::Time::now() - m->header.stamp).toSec());
  });
  ros::Subscriber statusSub = nh.subscribe<deformation_enrichment::EnrichmentStatus>("enrichment/status", 100, [&](const auto& s) {
    if (o.measureFrom.isZero() || s->header.stamp < o.measureFrom) return;
    o.withDetail += s->vertices_touched > 0;
    o.withTwoTools += s->tool_ids.size() == 2;
  });
  ros::Subscriber diagnosticsSub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("diagnostics", 10, [&](const auto& a) {
    for (const auto& status : a->status)
      for (const auto& value : status.values)
        if (value.key.rfind("mesh states lost in the input queue", 0) == 0) o.lostBeforeTheNode = std::stol(value.value);
  });
  ros::Subscriber markerSub = nh.subscribe<visualization_msgs::MarkerArray>("enrichment/markers", 1, [&](const auto&) { ++o.markers; });
  header.stamp = ros::Time::now();
  restPub.publish(de::ros_layer::messageFromTriangleMesh(surface, header));
  sensor_msgs::PointCloud2 cloud = de::ros_layer::cloudFromPositions(rest, header);
  if (!waitForNode(nh, statePub, cloud)) {
    std::fprintf(stderr, "soak: the enrichment node did not answer within 120 s\n");
    return 1;
  }
  const int pid = findProcess(processName);
  if (pid == 0) std::fprintf(stderr, "soak: no process %s to watch the memory of\n", processName.c_str());
  o.measureFrom = ros::Time::now();
  const Driven driven = drive(seconds, stateRate, poseRate, rest, cloud, statePub, posePubA, posePubB, pid);
  // The last states on their way back.
  for (ros::WallTime end = ros::WallTime::now() + ros::WallDuration(3.0); ros::ok() && o.received < driven.sent && ros::WallTime::now() < end;) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  return report(seconds, rest.cols(), driven, o) ? 0 : 1;
}
