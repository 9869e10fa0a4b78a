// Watches a running enrichment for a bounded time, then prints what happened (messages in and out,
// latency percentiles, NaN check) and exits: 0 when enriched states arrived and all were finite.
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deformation_enrichment/EnrichmentStatus.h"
#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::parameter;

namespace {
double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(std::min<double>(values.size() - 1, std::floor(p / 100.0 * values.size())))];
}
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_monitor");
  ros::NodeHandle nh, pnh("~");
  const double duration = parameter(pnh, "duration", 10.0, [](double v) { return v > 0.0 && std::isfinite(v); }, "> 0 seconds");
  const std::string summaryFile = parameter<std::string>(pnh, "summary_file", "");

  uint64_t inputs = 0, outputs = 0, nonFinite = 0, statuses = 0, withContact = 0, enrichedStates = 0;
  double maxConfidence = 0.0, maxTouched = 0.0;
  std::vector<double> latencyMs;
  ros::Subscriber in = nh.subscribe<sensor_msgs::PointCloud2>("mesh_state", 10, [&](const auto&) { ++inputs; });
  ros::Subscriber out = nh.subscribe<sensor_msgs::PointCloud2>(
      "enriched_mesh_state", 10, [&](const sensor_msgs::PointCloud2ConstPtr& cloud) {
        latencyMs.push_back((ros::Time::now() - cloud->header.stamp).toSec() * 1e3);
        ++outputs;
        if (!de::ros_layer::positionsFromCloud(*cloud).allFinite()) ++nonFinite;
      });
  ros::Subscriber status = nh.subscribe<de::EnrichmentStatus>("status", 10, [&](const de::EnrichmentStatusConstPtr& s) {
    ++statuses;
    if (!s->tool_ids.empty()) ++withContact;
    if (s->vertices_touched > 0) ++enrichedStates;
    maxConfidence = std::max(maxConfidence, static_cast<double>(s->confidence));
    maxTouched = std::max(maxTouched, static_cast<double>(s->vertices_touched));
  });

  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(duration);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.002).sleep();
  }
  char summary[1024];
  std::snprintf(summary, sizeof(summary),
                "{\"seconds\": %.1f, \"mesh_states_in\": %lu, \"enriched_out\": %lu, \"status_messages\": %lu, "
                "\"states_with_contact\": %lu, \"states_with_detail\": %lu, \"max_vertices_touched\": %.0f, "
                "\"max_confidence\": %.3f, \"non_finite_outputs\": %lu, \"latency_ms\": {\"p50\": %.3f, "
                "\"p90\": %.3f, \"p99\": %.3f, \"max\": %.3f}}",
                duration, inputs, outputs, statuses, withContact, enrichedStates, maxTouched, maxConfidence, nonFinite,
                percentile(latencyMs, 50),
                percentile(latencyMs, 90), percentile(latencyMs, 99), percentile(latencyMs, 100));
  std::printf("demo summary: %s\n", summary);
  std::fflush(stdout);
  if (!summaryFile.empty()) {
    try {
      de::writeFileAtomically(summaryFile, std::string(summary) + "\n");
    } catch (const de::Error& e) {
      ROS_ERROR("demo monitor: %s", e.what());
      return 1;
    }
  }
  const bool ok = outputs > 0 && nonFinite == 0;
  ros::shutdown();
  return ok ? 0 : 1;
}
