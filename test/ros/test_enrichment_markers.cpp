// The rviz markers of the enrichment without the node: the coarse surface and the fine truth beside the
// enriched one, the colour bar's ends against the surface's colours, strain colours, and the marker
// parameters. Linked into
// test_enrichment_knobs (the parameter test needs its master).
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"
#include "deformation_enrichment/ros/enrichment_node_parameters.hpp"

namespace de = deformation_enrichment;

namespace {

// A flat 1 cm square at z = 0, counter-clockwise seen from above (normal +z, like the slab's top).
de::mesh::TriangleMesh flatSquare() {
  de::mesh::TriangleMesh square;
  square.vertices.resize(3, 4);
  square.vertices << 0, 0.01, 0.01, 0, 0, 0, 0.01, 0.01, 0, 0, 0, 0;
  square.triangles.resize(3, 2);
  square.triangles << 0, 0, 1, 2, 2, 3;
  return square;
}

const visualization_msgs::Marker* find(const visualization_msgs::MarkerArray& array, const std::string& ns, int id) {
  for (const auto& marker : array.markers)
    if (marker.ns == ns && marker.id == id) return &marker;
  return nullptr;
}

void expectSameColor(const std_msgs::ColorRGBA& a, const std_msgs::ColorRGBA& b) {
  EXPECT_NEAR(a.r, b.r, 1e-5);
  EXPECT_NEAR(a.g, b.g, 1e-5);
  EXPECT_NEAR(a.b, b.b, 1e-5);
  EXPECT_FLOAT_EQ(a.a, b.a);
}

// The colour bar's colour at its bottom (lowest z) or top end.
std_msgs::ColorRGBA barEnd(const visualization_msgs::Marker& bar, bool top) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < bar.points.size(); ++i)
    if (top ? bar.points[i].z > bar.points[best].z : bar.points[i].z < bar.points[best].z) best = i;
  return bar.colors[best];
}

TEST(EnrichmentMarkers, CoarseSurfaceBesideTheEnrichedOneAndColourBarEndsMatchTheSurface) {
  const de::mesh::TriangleMesh rest = flatSquare();
  const Eigen::Matrix3Xf input = rest.vertices.cast<float>();
  de::ros_layer::MarkerOptions options;
  options.coarseOffset = Eigen::Vector3d(0.0, -0.11, 0.0);
  std_msgs::Header header;
  header.frame_id = "slab";
  for (const double added : {0.0, options.displacementScale}) {
    // A uniform lift keeps the square flat: every vertex shows the colour of `added` on the flat top.
    const Eigen::Matrix3Xf enriched = input.colwise() + Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(added));
    const auto array = de::ros_layer::enrichmentMarkers(header, rest, input, enriched, {}, options);
    ASSERT_FALSE(array.markers.empty());
    const auto& surface = array.markers[0];
    EXPECT_EQ(surface.ns, "enriched_surface");
    ASSERT_EQ(surface.points.size(), 6u);
    ASSERT_EQ(surface.colors.size(), 6u);
    const auto* coarse = find(array, "coarse_surface", 0);
    ASSERT_NE(coarse, nullptr);
    EXPECT_EQ(coarse->type, visualization_msgs::Marker::TRIANGLE_LIST);
    ASSERT_EQ(coarse->points.size(), surface.points.size());
    for (std::size_t i = 0; i < coarse->points.size(); ++i) {
      const int v = rest.triangles(static_cast<int>(i % 3), static_cast<int>(i / 3));
      EXPECT_NEAR(coarse->points[i].x, input(0, v) + options.coarseOffset.x(), 1e-7);
      EXPECT_NEAR(coarse->points[i].y, input(1, v) + options.coarseOffset.y(), 1e-7);
      EXPECT_NEAR(coarse->points[i].z, input(2, v) + options.coarseOffset.z(), 1e-7);
    }
    const auto* bar = find(array, "colour_bar", 0);
    ASSERT_NE(bar, nullptr);
    ASSERT_EQ(bar->colors.size(), bar->points.size());
    for (const auto& color : surface.colors) expectSameColor(color, barEnd(*bar, /*top=*/added > 0.0));
    EXPECT_EQ(bar->header.frame_id, "slab");
  }
}

TEST(EnrichmentMarkers, NoCoarseSurfaceWithoutAnOffset) {
  const de::mesh::TriangleMesh rest = flatSquare();
  const Eigen::Matrix3Xf input = rest.vertices.cast<float>();
  const auto array = de::ros_layer::enrichmentMarkers({}, rest, input, input, {}, de::ros_layer::MarkerOptions());
  EXPECT_EQ(find(array, "coarse_surface", 0), nullptr);
  EXPECT_NE(find(array, "colour_bar", 0), nullptr);
}

TEST(EnrichmentMarkers, FineTruthBesideTheEnrichedOneColouredByTheEnrichedError) {
  const de::mesh::TriangleMesh rest = flatSquare();
  const Eigen::Matrix3Xf input = rest.vertices.cast<float>();
  de::ros_layer::MarkerOptions options;
  options.fineOffset = Eigen::Vector3d(0.0, 0.11, 0.0);
  // The enrichment got vertex 0 exactly right and every other vertex wrong by the full colour scale.
  Eigen::Matrix3Xf fine = input;
  fine.row(2).setConstant(-0.002f);
  Eigen::Matrix3Xf enriched = fine;
  enriched.rightCols(3).row(2).array() += static_cast<float>(options.displacementScale);
  const auto array = de::ros_layer::enrichmentMarkers({}, rest, input, enriched, {}, options, &fine);
  const auto* truth = find(array, "fine_surface", 0);
  ASSERT_NE(truth, nullptr);
  const auto* bar = find(array, "colour_bar", 0);
  ASSERT_NE(bar, nullptr);
  ASSERT_EQ(truth->points.size(), 6u);
  for (std::size_t i = 0; i < truth->points.size(); ++i) {
    const int v = rest.triangles(static_cast<int>(i % 3), static_cast<int>(i / 3));
    EXPECT_NEAR(truth->points[i].y, fine(1, v) + options.fineOffset.y(), 1e-7);
    EXPECT_NEAR(truth->points[i].z, fine(2, v), 1e-7);
    expectSameColor(truth->colors[i], barEnd(*bar, /*top=*/v != 0));
  }
  // The bar stands right of the rightmost surface, the fine truth's.
  for (const auto& p : bar->points) EXPECT_GT(p.y, 0.01 + options.fineOffset.y());
  const Eigen::Matrix3Xf tooFew = fine.leftCols(3);
  EXPECT_THROW(de::ros_layer::enrichmentMarkers({}, rest, input, enriched, {}, options, &tooFew), de::InvalidInputError);
  // Without a truth, or without an offset, there is no fine surface.
  EXPECT_EQ(find(de::ros_layer::enrichmentMarkers({}, rest, input, enriched, {}, options), "fine_surface", 0), nullptr);
  EXPECT_EQ(find(de::ros_layer::enrichmentMarkers({}, rest, input, enriched, {}, de::ros_layer::MarkerOptions(), &fine),
                 "fine_surface", 0),
            nullptr);
}

TEST(EnrichmentMarkers, StrainColoursShowEachTrianglesLargestPrincipalStrain) {
  const de::mesh::TriangleMesh rest = flatSquare();
  const Eigen::Matrix3Xf input = rest.vertices.cast<float>();
  de::ros_layer::MarkerOptions options;
  options.color = de::ros_layer::MarkerOptions::Color::Strain;
  options.strainScale = 0.1;
  // Stretched 5 % along x and compressed 3 % along y, rotated and lifted (no strain): both triangles have
  // the largest principal strain 0.05, half the scale: the colour bar's middle.
  Eigen::Matrix3f deform = Eigen::AngleAxisf(0.4f, Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
  deform = deform * Eigen::Vector3f(1.05f, 0.97f, 1.0f).asDiagonal();
  const Eigen::Matrix3Xf enriched = (deform * input).colwise() + Eigen::Vector3f(0.0f, 0.0f, 0.001f);
  const auto stretched = de::ros_layer::enrichmentMarkers({}, rest, input, enriched, {}, options);
  const auto unstrained = de::ros_layer::enrichmentMarkers({}, rest, input, input, {}, options);
  const auto* bar = find(unstrained, "colour_bar", 0);
  ASSERT_NE(bar, nullptr);
  const std_msgs::ColorRGBA zero = barEnd(*bar, false), full = barEnd(*bar, true);
  ASSERT_EQ(unstrained.markers[0].colors.size(), 6u);
  for (const auto& color : unstrained.markers[0].colors) expectSameColor(color, zero);
  // The rotated square is lit differently; its colour relative to the flat one's scale is the same.
  const auto& colors = stretched.markers[0].colors;
  ASSERT_EQ(colors.size(), 6u);
  const double light = colors[0].g / (0.5 * (zero.g + full.g));
  for (const auto& color : colors) {
    EXPECT_NEAR(color.r, light * 0.5 * (zero.r + full.r), 1e-4);
    EXPECT_NEAR(color.b, light * 0.5 * (zero.b + full.b), 1e-4);
  }
  const auto* title = find(stretched, "colour_bar", 3);
  ASSERT_NE(title, nullptr);
  EXPECT_EQ(title->text, "principal strain");
  EXPECT_EQ(find(stretched, "colour_bar", 2)->text, "10 %");
}

TEST(EnrichmentMarkers, OffsetParametersAreVectorsOfThreeElseOff) {
  ros::NodeHandle nh("marker_options_test");
  nh.setParam("marker_coarse_offset", std::vector<double>{0.0, -0.11, 0.01});
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).coarseOffset.isApprox(Eigen::Vector3d(0.0, -0.11, 0.01)));
  nh.setParam("marker_coarse_offset", std::vector<double>{0.1, 0.2});
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).coarseOffset.isZero());
  nh.deleteParam("marker_coarse_offset");
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).coarseOffset.isZero());
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).fineOffset.isZero());
  nh.setParam("marker_fine_offset", std::vector<double>{0.0, 0.11, 0.0});
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).fineOffset.isApprox(Eigen::Vector3d(0.0, 0.11, 0.0)));
  nh.setParam("marker_fine_offset", std::vector<double>{0.0, std::nan(""), 0.0});
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).fineOffset.isZero());
  nh.setParam("marker_fine_offset", std::string("[0, 0.105, 0]"));  // what rosrun's _marker_fine_offset:=... gives
  EXPECT_TRUE(de::ros_layer::readMarkerOptions(nh).fineOffset.isZero());
  nh.deleteParam("marker_fine_offset");
  EXPECT_EQ(de::ros_layer::readMarkerOptions(nh).color, de::ros_layer::MarkerOptions::Color::Displacement);
  nh.setParam("marker_color", "strain");
  EXPECT_EQ(de::ros_layer::readMarkerOptions(nh).color, de::ros_layer::MarkerOptions::Color::Strain);
  nh.setParam("marker_color", "pressure");
  EXPECT_EQ(de::ros_layer::readMarkerOptions(nh).color, de::ros_layer::MarkerOptions::Color::Displacement);
  nh.setParam("marker_strain_scale", 0.0);
  nh.setParam("marker_displacement_scale", std::nan(""));
  const auto fallback = de::ros_layer::readMarkerOptions(nh);
  EXPECT_EQ(fallback.strainScale, de::ros_layer::MarkerOptions().strainScale) << "a zero scale would colour NaN";
  EXPECT_EQ(fallback.displacementScale, de::ros_layer::MarkerOptions().displacementScale);
}

}  // namespace
