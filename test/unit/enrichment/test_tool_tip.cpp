// The tool tip geometry: signed distances of the URDF primitives, clear errors for unusable URDFs, triangle
// distances against a dense-sampling oracle, and the tool proximity's use of the pose orientation and of the
// surface triangles.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"
#include "deformation_enrichment/enrichment/tool_proximity.hpp"
#include "deformation_enrichment/enrichment/tool_tip.hpp"

namespace de = deformation_enrichment;

namespace {

TEST(ToolTipGeometry, SignedDistancesOfUrdfPrimitivesAndClearErrors) {
  // One tree (urdfdom needs a single root): every link hangs off "base" by a fixed joint.
  std::string urdf = R"(<robot name="tip_test"><link name="base"/>
    <link name="ball"><collision><geometry><sphere radius="0.004"/></geometry></collision></link>
    <link name="rod"><collision><origin xyz="0 0 0.01"/><geometry><cylinder radius="0.002" length="0.02"/></geometry></collision></link>
    <link name="block"><collision><geometry><box size="0.02 0.04 0.06"/></geometry></collision></link>
    <link name="bare"/>
    <link name="scan"><collision><geometry><mesh filename="package://x/tip.stl"/></geometry></collision></link>
  )";
  for (const char* link : {"ball", "rod", "block", "bare", "scan"})
    urdf += std::string("<joint name=\"") + link + "_joint\" type=\"fixed\"><parent link=\"base\"/><child link=\"" + link +
            "\"/></joint>";
  urdf += "</robot>";
  const auto ball = de::enrichment::toolTipFromUrdf(urdf, "ball");
  EXPECT_NEAR(ball.signedDistance(Eigen::Vector3d(0, 0, 0.01)), 0.006, 1e-12);
  EXPECT_NEAR(ball.signedDistance(Eigen::Vector3d::Zero()), -0.004, 1e-12);
  const auto rod = de::enrichment::toolTipFromUrdf(urdf, "rod");  // spans z in [0, 0.02] of the link
  EXPECT_NEAR(rod.signedDistance(Eigen::Vector3d(0, 0, -0.003)), 0.003, 1e-12);
  EXPECT_NEAR(rod.signedDistance(Eigen::Vector3d(0.005, 0, 0.01)), 0.003, 1e-12);
  EXPECT_NEAR(rod.signedDistance(Eigen::Vector3d(0.005, 0, -0.004)), 0.005, 1e-12);
  const auto block = de::enrichment::toolTipFromUrdf(urdf, "block");
  EXPECT_NEAR(block.signedDistance(Eigen::Vector3d(0.02, 0, 0)), 0.01, 1e-12);
  EXPECT_NEAR(block.signedDistance(Eigen::Vector3d(0, 0, 0.01)), -0.01, 1e-12);
  EXPECT_NEAR(de::enrichment::ToolTip().signedDistance(Eigen::Vector3d(0.003, 0.004, 0)), 0.005, 1e-12);
  auto message = [&](const std::string& xml, const std::string& link) {
    try {
      de::enrichment::toolTipFromUrdf(xml, link);
    } catch (const de::InvalidInputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(urdf, "missing").find("no link 'missing'"), std::string::npos);
  EXPECT_NE(message(urdf, "bare").find("no collision geometry"), std::string::npos);
  EXPECT_NE(message(urdf, "scan").find("mesh collision geometry is not supported"), std::string::npos);
  EXPECT_NE(message("<robot", "ball").find("not a valid URDF"), std::string::npos);
  EXPECT_NE(message("", "ball").find("empty"), std::string::npos);
}

TEST(ToolTipGeometry, TriangleDistanceMatchesADenseSamplingOfTheTriangle) {
  // Oracle: the smallest signed distance over a 300 x 300 barycentric grid of the triangle (an upper bound
  // within grid spacing of the true minimum). Random triangles and tip poses, all three primitives.
  const std::string urdf = R"(<robot name="shapes"><link name="base"/>
    <link name="ball"><collision><origin xyz="0.001 0 0.002"/><geometry><sphere radius="0.004"/></geometry></collision></link>
    <link name="rod"><collision><origin xyz="0 0.002 0" rpy="0.3 0.2 0"/><geometry><cylinder radius="0.002" length="0.02"/></geometry></collision></link>
    <link name="block"><collision><origin rpy="0.5 -0.4 0.2"/><geometry><box size="0.006 0.01 0.004"/></geometry></collision></link>
    <joint name="j1" type="fixed"><parent link="base"/><child link="ball"/></joint>
    <joint name="j2" type="fixed"><parent link="base"/><child link="rod"/></joint>
    <joint name="j3" type="fixed"><parent link="base"/><child link="block"/></joint></robot>)";
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-0.015, 0.015);
  for (const char* link : {"ball", "rod", "block"}) {
    const de::enrichment::ToolTip tip = de::enrichment::toolTipFromUrdf(urdf, link);
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::Vector3d a(coordinate(rng), coordinate(rng), coordinate(rng)), b(coordinate(rng), coordinate(rng), coordinate(rng)),
          c(coordinate(rng), coordinate(rng), coordinate(rng));
      double sampled = std::numeric_limits<double>::infinity();
      const int n = 300;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
          sampled = std::min(sampled, tip.signedDistance(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n)));
      const double spacing = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / n;
      Eigen::Vector3d closest;
      const double d = tip.triangleDistance(a, b, c, &closest);
      EXPECT_NEAR(tip.signedDistance(closest), d, 1e-12) << link << " trial " << trial << ": the point attains the distance";
      EXPECT_NEAR((closest - de::mesh::closestPointOnTriangle(closest, a, b, c)).norm(), 0.0, 1e-12) << "on the triangle";
      if (sampled > 0.0) {  // disjoint: alternating projections find the minimum (to 0.1 um)
        EXPECT_LE(d, sampled + 1e-6) << link << " trial " << trial;
        EXPECT_GE(d, sampled - 2.0 * spacing - 1e-6) << link << " trial " << trial;
      } else {
        // Alternating projections approach an intersection from outside and stop after a bounded number of
        // steps: some um above zero, how many depends on the compiler's rounding (13.5 um at worst seen, clang
        // -O2 with ASan; below 10 um with gcc), far below any contact distance (mm).
        EXPECT_LE(d, 1e-4) << link << " trial " << trial << ": the triangle cuts into the tip";
      }
    }
  }
}

TEST(ToolTipGeometry, TrianglesCatchATipOverACoarseTriangleThatNoVertexIsNear) {
  // One 4 cm square of two triangles; a 4 mm ball 1 mm above its centre: every vertex is > 2.4 cm away.
  const std::string urdf = R"(<robot name="b"><link name="ball"><collision><geometry><sphere radius="0.004"/></geometry>
    </collision></link></robot>)";
  const de::enrichment::ToolTip ball = de::enrichment::toolTipFromUrdf(urdf, "ball");
  Eigen::Matrix3Xf surface(3, 4);
  surface << -0.02f, 0.02f, 0.02f, -0.02f, -0.02f, -0.02f, 0.02f, 0.02f, 0.0f, 0.0f, 0.0f, 0.0f;
  Eigen::Matrix3Xi triangles(3, 2);
  triangles << 0, 0, 1, 2, 2, 3;
  Eigen::ArrayXf scratch;
  const Eigen::Isometry3d pose(Eigen::Translation3d(0.003, 0.0, 0.005));
  EXPECT_FALSE(de::enrichment::toolProximity(pose, ball, surface, 0.003, nullptr, scratch).inContact)
      << "the vertices alone are far from the ball";
  const auto touching = de::enrichment::toolProximity(pose, ball, surface, 0.003, &triangles, scratch);
  ASSERT_TRUE(touching.inContact) << "the triangles are 1 mm from the ball";
  EXPECT_LT((touching.point - Eigen::Vector3d(0.003, 0.0, 0.0)).norm(), 1e-9) << "the point under the ball";
  const Eigen::Isometry3d higher(Eigen::Translation3d(0.003, 0.0, 0.0075));  // 3.5 mm above: free
  EXPECT_FALSE(de::enrichment::toolProximity(higher, ball, surface, 0.003, &triangles, scratch).inContact);
}

TEST(ToolTipGeometry, ProximityUsesTheTipPoseOrientation) {
  // A rod (r = 2 mm, 40 mm long along its link's z, centred on the link origin) over a flat patch at z = 0.
  // At 10 mm height upright it pierces the surface (its lower end is 10 mm below); turned 90 degrees about y it lies
  // along x, 8 mm above (free); lowered to 5 mm, 3 mm above (in contact under its axis).
  const std::string urdf = R"(<robot name="rod_test"><link name="rod"><collision>
    <geometry><cylinder radius="0.002" length="0.04"/></geometry></collision></link></robot>)";
  const de::enrichment::ToolTip rod = de::enrichment::toolTipFromUrdf(urdf, "rod");
  Eigen::Matrix3Xf surface(3, 121);
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j) surface.col(11 * i + j) = Eigen::Vector3f(-0.025f + 0.005f * i, -0.025f + 0.005f * j, 0.0f);
  Eigen::ArrayXf scratch;
  const auto contact = [&](double z, const Eigen::Quaterniond& orientation) {
    const Eigen::Isometry3d pose = de::enrichment::toolLinkPose(Eigen::Vector3d(0.0025, 0.0, z), orientation, rod, "rod");
    return de::enrichment::toolProximity(pose, rod, surface, 0.0035, nullptr, scratch);
  };
  auto touching = contact(0.01, Eigen::Quaterniond::Identity());  // between grid columns
  ASSERT_TRUE(touching.inContact) << "upright, the rod pierces the surface";
  EXPECT_LE((touching.point - Eigen::Vector3d(0.0025, 0.0, 0.0)).norm(), 0.0036) << "a vertex under the rod's end";
  const Eigen::Quaterniond lying(std::sqrt(0.5), 0.0, std::sqrt(0.5), 0.0);
  EXPECT_FALSE(contact(0.01, lying).inContact) << "lying along x 10 mm up, the rod is 8 mm above the surface";
  touching = contact(0.005, lying);
  ASSERT_TRUE(touching.inContact) << "lying along x 5 mm up, the rod is 3 mm above the surface";
  EXPECT_NEAR(touching.point.z(), 0.0, 1e-9);
  EXPECT_LE(std::abs(touching.point.y()), 1e-6) << "the contact lies under the rod's axis";
  EXPECT_LE(std::abs(touching.point.x() - 0.0025), 0.0201) << "and along its length";
  // Not a unit quaternion: refused for a shaped tip, ignored by a point tip.
  EXPECT_THROW(contact(0.005, Eigen::Quaterniond(0.5, 0.0, 0.5, 0.0)), de::InvalidInputError);
  EXPECT_NO_THROW(de::enrichment::toolLinkPose(Eigen::Vector3d::Zero(), Eigen::Quaterniond(0, 0, 0, 0), {}, "point"));
  EXPECT_THROW(de::enrichment::toolLinkPose(Eigen::Vector3d(NAN, 0, 0), Eigen::Quaterniond::Identity(), {}, "point"),
               de::InvalidInputError);
}

}  // namespace
