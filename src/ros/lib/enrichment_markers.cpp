#include "deformation_enrichment/ros/enrichment_markers.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/triangle_deformation_gradient.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

// rviz draws a TRIANGLE_LIST with per-vertex colours unlit (its material turns lighting off then) and
// without them lights it with one normal per face, so the surfaces would look flat either way. The
// shading is therefore baked into the colours: a Lambert term of the smooth vertex normals under a fixed
// light from -y (the left of the demo's camera) only 22 degrees above the surface, bright enough that the
// flat top keeps ~3/4 of its colour. The enrichment's rim (~1 mm high on a 3 mm dent) has slopes of ~15
// degrees: lit from higher up they would differ from the flat top by a few percent only.
const Eigen::Vector3d kTowardLight = Eigen::Vector3d(0.35, -0.86, 0.375).normalized();
constexpr double kAmbient = 0.25, kLight = 1.4;
constexpr double kTextHeight = 0.006;  // [m]

double shade(const Eigen::Vector3d& normal) { return std::min(1.0, kAmbient + kLight * std::max(0.0, normal.dot(kTowardLight))); }

std_msgs::ColorRGBA rgb(double r, double g, double b) {
  std_msgs::ColorRGBA color;
  color.r = static_cast<float>(r);
  color.g = static_cast<float>(g);
  color.b = static_cast<float>(b);
  color.a = 1.0f;
  return color;
}

std_msgs::ColorRGBA shaded(std_msgs::ColorRGBA color, double s) {
  color.r = static_cast<float>(color.r * s);
  color.g = static_cast<float>(color.g * s);
  color.b = static_cast<float>(color.b * s);
  return color;
}

// 0 -> grey-blue, 1 -> red; affine in t, so colours interpolated over a triangle stay on the scale.
std_msgs::ColorRGBA heatColor(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return rgb(0.55 + 0.45 * t, 0.6 * (1.0 - t), 0.75 * (1.0 - t));
}

geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point result;
  result.x = p.x();
  result.y = p.y();
  result.z = p.z();
  return result;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

visualization_msgs::Marker text(const std_msgs::Header& header, const std::string& ns, int id,
                                const Eigen::Vector3d& at, const std::string& label) {
  visualization_msgs::Marker m = marker(header, ns, id, visualization_msgs::Marker::TEXT_VIEW_FACING);
  m.pose.position = point(at);
  m.scale.x = m.scale.y = m.scale.z = kTextHeight;
  m.color = rgb(1.0, 1.0, 1.0);
  m.text = label;
  return m;
}

// The surface at `positions` (+ offset), every stride-th triangle, the colour of each triangle's corner
// (colorOf(triangle, vertex)) shaded by the vertex normal.
visualization_msgs::Marker surface(const std_msgs::Header& header, const std::string& ns, const mesh::TriangleMesh& rest,
                                   const Eigen::Matrix3Xf& positions, const Eigen::Vector3d& offset, Eigen::Index stride,
                                   const std::function<std_msgs::ColorRGBA(Eigen::Index, int)>& colorOf) {
  const mesh::TriangleMesh deformed{positions.cast<double>(), rest.triangles};
  const Eigen::Matrix3Xd normals = mesh::vertexNormals(deformed);
  visualization_msgs::Marker m = marker(header, ns, 0, visualization_msgs::Marker::TRIANGLE_LIST);
  for (Eigen::Index t = 0; t < rest.numTriangles(); t += stride) {
    for (int k = 0; k < 3; ++k) {
      const int v = rest.triangles(k, t);
      m.points.push_back(point(deformed.vertices.col(v) + offset));
      m.colors.push_back(shaded(colorOf(t, v), shade(normals.col(v))));
    }
  }
  return m;
}

// An upright bar right of the surface (+y) in the y-z plane: one quad, bottom the colour of no added
// displacement, top of full scale, both shaded like the undeformed top face (normal +z) so that they are
// the colours seen there.
void addColourBar(visualization_msgs::MarkerArray& array, const std_msgs::Header& header, const Eigen::Vector3d& low,
                  const Eigen::Vector3d& high, const std::string& title, const std::string& fullScale,
                  const std::string& zero) {
  const double flat = shade(Eigen::Vector3d::UnitZ());
  const double x = 0.5 * (low.x() + high.x()), y0 = high.y() + 0.006, y1 = y0 + 0.008;
  const double z0 = high.z(), z1 = high.z() + 0.03;  // above the top, so that the surface hides none of it
  visualization_msgs::Marker bar = marker(header, "colour_bar", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  const Eigen::Vector3d corners[4] = {{x, y0, z0}, {x, y1, z0}, {x, y1, z1}, {x, y0, z1}};
  for (int c : {0, 1, 2, 0, 2, 3}) {
    bar.points.push_back(point(corners[c]));
    bar.colors.push_back(shaded(heatColor(c < 2 ? 0.0 : 1.0), flat));
  }
  array.markers.push_back(bar);
  array.markers.push_back(text(header, "colour_bar", 1, {x, y1 + 0.01, z0}, zero));
  array.markers.push_back(text(header, "colour_bar", 2, {x, y1 + 0.01, z1}, fullScale));
  array.markers.push_back(text(header, "colour_bar", 3, {x, y0, z1 + 0.008}, title));
}

void addContacts(visualization_msgs::MarkerArray& array, const std_msgs::Header& header,
                 const std::vector<TrackedContact>& contacts) {
  const auto action = contacts.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
  visualization_msgs::Marker points = marker(header, "contacts", 0, visualization_msgs::Marker::SPHERE_LIST);
  points.action = action;
  points.scale.x = points.scale.y = points.scale.z = 0.003;
  points.color = rgb(0.0, 1.0, 0.0);
  for (const auto& contact : contacts) points.points.push_back(point(contact.position));
  array.markers.push_back(points);

  visualization_msgs::Marker normals = marker(header, "contact_normals", 0, visualization_msgs::Marker::LINE_LIST);
  normals.action = action;
  normals.scale.x = 0.0005;
  normals.color = rgb(0.0, 1.0, 1.0);
  for (const auto& contact : contacts) {
    normals.points.push_back(point(contact.position));
    normals.points.push_back(point(contact.position + 0.01 * contact.normal));
  }
  array.markers.push_back(normals);
}

// The largest |principal stretch - 1| of each triangle of `positions` against `rest`; empty when a rest
// triangle is too degenerate for a deformation gradient (logged).
Eigen::VectorXd triangleStrain(const mesh::TriangleMesh& rest, const Eigen::Matrix3Xf& positions) {
  try {
    const Eigen::Matrix2Xd stretches = kinematics::principalStretches(rest, {positions.cast<double>(), rest.triangles});
    return (stretches.array() - 1.0).abs().colwise().maxCoeff().transpose();
  } catch (const Error& e) {
    ROS_ERROR_THROTTLE(10.0, "strain colours unavailable, showing the added displacement: %s", e.what());
    return {};
  }
}

std::string formatted(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

visualization_msgs::MarkerArray enrichmentMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const Eigen::Matrix3Xf& input, const Eigen::Matrix3Xf& enriched,
                                                  const std::vector<TrackedContact>& contacts,
                                                  const MarkerOptions& options, const Eigen::Matrix3Xf* fineTruth) {
  visualization_msgs::MarkerArray array;
  const Eigen::VectorXf added = (enriched - input).colwise().norm();
  const Eigen::Index stride = std::max<Eigen::Index>(1, (rest.numTriangles() + options.maxTriangles - 1) /
                                                            std::max(1, options.maxTriangles));
  const Eigen::VectorXd strain =
      options.color == MarkerOptions::Color::Strain ? triangleStrain(rest, enriched) : Eigen::VectorXd();
  if (strain.size() > 0) {
    array.markers.push_back(surface(header, "enriched_surface", rest, enriched, Eigen::Vector3d::Zero(), stride,
                                    [&](Eigen::Index t, int) { return heatColor(strain[t] / options.strainScale); }));
  } else {
    array.markers.push_back(surface(header, "enriched_surface", rest, enriched, Eigen::Vector3d::Zero(), stride,
                                    [&](Eigen::Index, int v) { return heatColor(added[v] / options.displacementScale); }));
  }
  // Labels above each surface's far edge (-x, away from the demo's camera).
  const Eigen::Vector3d low = rest.vertices.rowwise().minCoeff(), high = rest.vertices.rowwise().maxCoeff();
  const Eigen::Vector3d labelAt(low.x(), 0.5 * (low.y() + high.y()), high.z() + 0.01);
  array.markers.push_back(text(header, "enriched_surface", 1, labelAt, "enriched"));
  if (!options.coarseOffset.isZero()) {
    array.markers.push_back(surface(header, "coarse_surface", rest, input, options.coarseOffset, stride,
                                    [](Eigen::Index, int) { return rgb(0.7, 0.7, 0.7); }));
    array.markers.push_back(text(header, "coarse_surface", 1, labelAt + options.coarseOffset, "coarse input"));
  }
  if (fineTruth && fineTruth->cols() != enriched.cols())
    throw InvalidInputError("enrichment markers: a fine truth of " + std::to_string(fineTruth->cols()) + " points for a state of " +
                            std::to_string(enriched.cols()));
  const bool fineDrawn = !options.fineOffset.isZero() && fineTruth;
  if (fineDrawn) {
    const Eigen::VectorXf error = (enriched - *fineTruth).colwise().norm();
    array.markers.push_back(surface(header, "fine_surface", rest, *fineTruth, options.fineOffset, stride,
                                    [&](Eigen::Index, int v) { return heatColor(error[v] / options.displacementScale); }));
    array.markers.push_back(text(header, "fine_surface", 1, labelAt + options.fineOffset, "fine truth, coloured by the enriched error"));
  }
  // The colour bar right of the rightmost surface drawn.
  Eigen::Vector3d barHigh = high;
  if (!options.coarseOffset.isZero()) barHigh.y() = std::max(barHigh.y(), high.y() + options.coarseOffset.y());
  if (fineDrawn) barHigh.y() = std::max(barHigh.y(), high.y() + options.fineOffset.y());
  if (strain.size() > 0)
    addColourBar(array, header, low, barHigh, "principal strain", formatted("%.3g %%", 100.0 * options.strainScale), "0 %");
  else
    addColourBar(array, header, low, barHigh, "added displacement", formatted("%.3g mm", 1e3 * options.displacementScale), "0 mm");
  addContacts(array, header, contacts);
  return array;
}

}  // namespace deformation_enrichment::ros_layer
