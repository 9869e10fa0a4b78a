// eq. (16) blending and the eq. (1) displacement mapping with several contacts.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;

namespace {

cv::Mat patternStamp(int n, double phase) {
  cv::Mat s(n, n, CV_32FC3);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k)
      s.at<cv::Vec3f>(j, k) = cv::Vec3f(float(1e-3 * std::sin(0.3 * k + phase)), float(1e-3 * std::cos(0.2 * j)),
                                        float(2e-3 + 1e-4 * (j - k)));  // non-zero at the rim on purpose
  return s;
}

// Surface vertices: a flat grid z = 0 over [-L, L]^2 with spacing h.
Eigen::Matrix3Xd flatGrid(double L, double h) {
  const int n = static_cast<int>(std::round(2 * L / h)) + 1;
  Eigen::Matrix3Xd v(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) v.col(j * n + k) = Eigen::Vector3d(-L + k * h, -L + j * h, 0.0);
  return v;
}

en::ContactStamp contactAt(const Eigen::Vector3d& p, double angle, double R, double phase) {
  en::ContactStamp c;
  c.contact = p;
  c.frame = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  c.rotation = Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  c.stamp = patternStamp(33, phase);
  c.radius = R;
  return c;
}

// Full-surface e (zero where untouched).
Eigen::Matrix3Xd denseEnrichment(en::StampMapper& mapper, const std::vector<en::ContactStamp>& contacts) {
  en::SurfaceEnrichment e;
  mapper.map(contacts, e);
  Eigen::Matrix3Xd dense = Eigen::Matrix3Xd::Zero(3, mapper.size());
  for (std::size_t k = 0; k < e.vertices.size(); ++k) dense.col(e.vertices[k]) = e.displacements.col(static_cast<Eigen::Index>(k));
  return dense;
}

// Two triangles per cell of an n x n vertex grid (ids offset + j n + k), counter-clockwise from +z.
Eigen::Matrix3Xi gridTriangles(int n, int offset = 0) {
  Eigen::Matrix3Xi t(3, 2 * (n - 1) * (n - 1));
  Eigen::Index f = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int k = 0; k + 1 < n; ++k) {
      const int a = offset + j * n + k, b = a + 1, c = a + n + 1, d = a + n;
      t.col(f++) = Eigen::Vector3i(a, b, c);
      t.col(f++) = Eigen::Vector3i(a, c, d);
    }
  return t;
}

// e as the mapper computed it before surface reach, written plainly: every vertex of the 3D ball (the
// squared distance summed as nanoflann's L2_Simple does, its test `< R^2`), rim weight, facing test.
Eigen::Matrix3Xd wholeBallReference(const en::StampMapper& mapper, const Eigen::Matrix3Xd& normals,
                                    const std::vector<en::ContactStamp>& contacts, std::vector<int>& touched) {
  const Eigen::Matrix3Xd& rest = mapper.restVertices();
  Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, rest.cols());
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(rest.cols());
  for (const en::ContactStamp& c : contacts) {
    const Eigen::Matrix3d RB = c.rotation * c.frame;
    for (Eigen::Index v = 0; v < rest.cols(); ++v) {
      double d2 = 0.0;
      for (int i = 0; i < 3; ++i) d2 += (c.contact[i] - rest(i, v)) * (c.contact[i] - rest(i, v));
      // No vertex near the sphere: the result must not hinge on round-off in the distance.
      EXPECT_GT(std::abs(d2 - c.radius * c.radius), 1e-9 * c.radius * c.radius) << v;
      if (!(d2 < c.radius * c.radius)) continue;
      const double a = mapper.rimWeight(std::sqrt(d2) * (1.0 / c.radius));  // rounded as the mapper rounds it
      if (a == 0.0 || (normals.cols() != 0 && normals.col(v).dot(c.frame.col(2)) < 0.0)) continue;
      const Eigen::Vector3d x = rest.col(v) - c.contact;
      sum.col(v) += a * (RB * en::sampleStamp(c.stamp, c.radius, c.frame.col(0).dot(x), c.frame.col(1).dot(x)));
      weight[v] += a;
    }
  }
  touched.clear();
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    if (weight[v] != 0.0) {
      touched.push_back(static_cast<int>(v));
      sum.col(v) /= std::max(1.0, weight[v]);
    }
  return sum;
}

}  // namespace

TEST(StampBlending, Eq16IsTheWeightedSum) {
  const std::vector<cv::Mat> stamps = {patternStamp(9, 0.0), patternStamp(9, 1.0), patternStamp(9, 2.0)};
  const Eigen::Vector3d w(0.5, -0.25, 0.0);
  const cv::Mat blended = en::blendStamps(stamps, w);
  for (int j = 0; j < 9; ++j)
    for (int k = 0; k < 9; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(blended.at<cv::Vec3f>(j, k)[c], 0.5 * stamps[0].at<cv::Vec3f>(j, k)[c] - 0.25 * stamps[1].at<cv::Vec3f>(j, k)[c], 1e-9);
  EXPECT_THROW(en::blendStamps(stamps, Eigen::Vector2d(1, 1)), de::InvalidInputError);
  EXPECT_THROW(en::blendStamps({patternStamp(9, 0), patternStamp(8, 0)}, Eigen::Vector2d(1, 1)), de::InvalidInputError);
  EXPECT_THROW(en::blendStamps({}, Eigen::VectorXd()), de::InvalidInputError);
  EXPECT_THROW(en::blendStamps(stamps, Eigen::Vector3d(1, std::nan(""), 0)), de::InvalidInputError);
}

TEST(StampBlending, SingleContactEqualsTheStampAndLeavesTheRestUntouched) {
  const double R = 0.01;
  en::StampMapper mapper(flatGrid(0.03, 0.0005), 0.2);
  const en::ContactStamp c = contactAt(Eigen::Vector3d(0.004, -0.002, 0.0), 0.4, R, 0.0);
  en::SurfaceEnrichment e;
  mapper.map({c}, e);
  ASSERT_FALSE(e.vertices.empty());
  std::size_t inner = 0;
  for (std::size_t k = 0; k < e.vertices.size(); ++k) {
    const Eigen::Vector3d x = mapper.restVertices().col(e.vertices[k]);
    const double r = (x - c.contact).norm() / R;
    ASSERT_LE(r, 1.0);
    const Eigen::Vector3d local = c.frame.transpose() * (x - c.contact);
    const Eigen::Vector3d stamp = c.rotation * c.frame * en::sampleStamp(c.stamp, R, local.x(), local.y());
    const Eigen::Vector3d expected = mapper.rimWeight(r) * stamp;
    EXPECT_LT((e.displacements.col(static_cast<Eigen::Index>(k)) - expected).norm(), 1e-15);
    if (r <= 0.8) {
      EXPECT_LT((e.displacements.col(static_cast<Eigen::Index>(k)) - stamp).norm(), 1e-16);  // inside the band: R B Psi
      ++inner;
    }
  }
  EXPECT_GT(inner, 700u);  // ~ pi (0.8 R / h)^2 = 804
  // Every vertex within 0.99 R is touched, none beyond R.
  std::size_t within = 0;
  for (Eigen::Index v = 0; v < mapper.size(); ++v) within += (mapper.restVertices().col(v) - c.contact).norm() < 0.99 * R;
  EXPECT_GE(e.vertices.size(), within);

  Eigen::Matrix3Xd state = mapper.restVertices();
  state.row(2).array() += 0.001 * state.row(0).array();  // some coarse deformation
  const Eigen::Matrix3Xd coarse = state;
  mapper.apply(e, state);
  std::vector<bool> touched(mapper.size(), false);
  for (int v : e.vertices) touched[v] = true;
  for (Eigen::Index v = 0; v < mapper.size(); ++v)
    if (!touched[v]) {
      ASSERT_EQ(std::memcmp(state.col(v).data(), coarse.col(v).data(), 3 * sizeof(double)), 0) << v;
    }
}

TEST(StampBlending, HardCutWithZeroBandIsThePlainStamp) {
  const double R = 0.01;
  en::StampMapper mapper(flatGrid(0.02, 0.001), 0.0);
  const en::ContactStamp c = contactAt(Eigen::Vector3d::Zero(), 0.0, R, 0.0);
  en::SurfaceEnrichment e;
  mapper.map({c}, e);
  for (std::size_t k = 0; k < e.vertices.size(); ++k) {
    const Eigen::Vector3d x = mapper.restVertices().col(e.vertices[k]);
    const Eigen::Vector3d expected = c.rotation * c.frame * en::sampleStamp(c.stamp, R, x.x(), x.y());
    EXPECT_LT((e.displacements.col(static_cast<Eigen::Index>(k)) - expected).norm(), 1e-16);
  }
}

TEST(StampBlending, OverlappingStampsStayContinuous) {
  // Two overlapping contacts whose stamps are non-zero at their rims. Along a line through both, the
  // largest jump between neighbouring vertices must shrink with the spacing (continuity), not stay at
  // the size of a stamp value (a seam).
  const double R = 0.01;
  const std::vector<en::ContactStamp> contacts = {contactAt(Eigen::Vector3d(-0.004, 0.0, 0.0), 0.3, R, 0.0),
                                                  contactAt(Eigen::Vector3d(0.005, 0.001, 0.0), -1.0, R, 2.0)};
  double previousJump = 0.0;
  for (double h : {2e-4, 1e-4, 5e-5}) {
    const int n = static_cast<int>(std::round(0.04 / h)) + 1;
    Eigen::Matrix3Xd line(3, n);
    for (int i = 0; i < n; ++i) line.col(i) = Eigen::Vector3d(-0.02 + i * h, 0.0005, 0.0);
    en::StampMapper mapper(line, 0.2);
    const Eigen::Matrix3Xd e = denseEnrichment(mapper, contacts);
    double jump = 0.0;
    for (int i = 0; i + 1 < n; ++i) jump = std::max(jump, (e.col(i + 1) - e.col(i)).norm());
    EXPECT_GT(e.cwiseAbs().maxCoeff(), 1e-3);  // the stamps are there
    if (previousJump > 0.0) {
      EXPECT_LT(jump, 0.7 * previousJump) << "spacing " << h;
    }
    previousJump = jump;
  }
  EXPECT_LT(previousJump, 2.5e-4);  // slope < 5 m^-1 (rim smoothstep 1.5 / 0.2R times ~2e-3), vs a seam of ~1e-3

  // Contrast: a hard cut (band 0) has a seam of the size of the stamp value, whatever the spacing.
  Eigen::Matrix3Xd line(3, 801);
  for (int i = 0; i < 801; ++i) line.col(i) = Eigen::Vector3d(-0.02 + i * 5e-5, 0.0005, 0.0);
  en::StampMapper hard(line, 0.0);
  const Eigen::Matrix3Xd e = denseEnrichment(hard, contacts);
  double jump = 0.0;
  for (int i = 0; i < 800; ++i) jump = std::max(jump, (e.col(i + 1) - e.col(i)).norm());
  EXPECT_GT(jump, 5e-4);
}

TEST(StampBlending, CoincidingContactsDoNotDoubleTheDisplacement) {
  const double R = 0.01;
  en::StampMapper mapper(flatGrid(0.015, 0.001), 0.2);
  const en::ContactStamp c = contactAt(Eigen::Vector3d(0.001, 0.0, 0.0), 0.2, R, 0.5);
  const Eigen::Matrix3Xd single = denseEnrichment(mapper, {c});
  const Eigen::Matrix3Xd twice = denseEnrichment(mapper, {c, c});
  // Inside (1 - band) R both weights are 1, the sum 2 is normalised: exactly one stamp.
  for (Eigen::Index v = 0; v < mapper.size(); ++v) {
    const double r = (mapper.restVertices().col(v) - c.contact).norm() / R;
    if (r <= 0.8) {
      EXPECT_LT((twice.col(v) - single.col(v)).norm(), 1e-15);
    }
    if (r > 0.8 && r < 1.0) {
      EXPECT_LE(twice.col(v).norm(), 2.0 * single.col(v).norm() + 1e-15);
    }
  }
  // Calling again (scratch reuse) gives the same answer.
  EXPECT_EQ(denseEnrichment(mapper, {c}), single);
  EXPECT_EQ(denseEnrichment(mapper, {}).cwiseAbs().maxCoeff(), 0.0);
}

TEST(StampBlending, NormalsKeepTheFarSideOfAThinPartUntouched) {
  // A 3 mm thick plate: top face (normal +z) and bottom face (normal -z) both inside a 1 cm ball.
  const Eigen::Matrix3Xd top = flatGrid(0.015, 0.001);
  Eigen::Matrix3Xd bottom = top;
  bottom.row(2).setConstant(-0.003);
  Eigen::Matrix3Xd rest(3, 2 * top.cols()), normals(3, 2 * top.cols());
  rest << top, bottom;
  normals.leftCols(top.cols()).colwise() = Eigen::Vector3d::UnitZ();
  normals.rightCols(top.cols()).colwise() = -Eigen::Vector3d::UnitZ();
  const en::ContactStamp c = contactAt(Eigen::Vector3d::Zero(), 0.2, 0.01, 0.0);
  en::SurfaceEnrichment withoutNormals, withNormals;
  en::StampMapper plain(rest, 0.2);
  plain.map({c}, withoutNormals);
  en::StampMapper facing(rest, 0.2, normals);
  facing.map({c}, withNormals);
  EXPECT_GT(withoutNormals.vertices.back(), top.cols());  // the plain ball reaches the bottom face
  ASSERT_FALSE(withNormals.vertices.empty());
  EXPECT_LT(withNormals.vertices.back(), top.cols());  // the facing test keeps it untouched
  // On the top face both agree.
  std::size_t k = 0;
  for (; k < withNormals.vertices.size(); ++k) {
    EXPECT_EQ(withNormals.vertices[k], withoutNormals.vertices[k]);
    EXPECT_EQ(withNormals.displacements.col(static_cast<Eigen::Index>(k)), withoutNormals.displacements.col(static_cast<Eigen::Index>(k)));
  }
  EXPECT_THROW((en::StampMapper{rest, 0.2, normals.leftCols(3)}), de::InvalidInputError);
}

TEST(StampBlending, BadInputThrows) {
  EXPECT_THROW(en::StampMapper{Eigen::Matrix3Xd(3, 0)}, de::InvalidInputError);
  Eigen::Matrix3Xd bad = Eigen::Matrix3Xd::Zero(3, 4);
  bad(0, 1) = std::nan("");
  EXPECT_THROW(en::StampMapper{bad}, de::InvalidInputError);
  EXPECT_THROW((en::StampMapper{Eigen::Matrix3Xd::Zero(3, 4), 1.0}), de::InvalidInputError);
  en::StampMapper mapper(flatGrid(0.01, 0.001));
  en::SurfaceEnrichment e;
  en::ContactStamp c = contactAt(Eigen::Vector3d::Zero(), 0.0, 0.01, 0.0);
  c.frame *= 2.0;
  EXPECT_THROW(mapper.map({c}, e), de::InvalidInputError);
  c = contactAt(Eigen::Vector3d::Zero(), 0.0, 0.01, 0.0);
  c.contact.x() = std::nan("");
  EXPECT_THROW(mapper.map({c}, e), de::InvalidInputError);
  c = contactAt(Eigen::Vector3d::Zero(), 0.0, -1.0, 0.0);
  EXPECT_THROW(mapper.map({c}, e), de::InvalidInputError);
  Eigen::Matrix3Xd wrong(3, 2);
  EXPECT_THROW(mapper.apply(e, wrong), de::InvalidInputError);
}

// Surface reach: given the rest triangles, a stamp reaches the part of its ball connected to the contact
// through edges inside the ball, not whatever the 3D ball holds.
namespace {
constexpr double kHalf = 0.03, kSpacing = 0.001, kRadius = 0.02;
constexpr int kGrid = 61;  // vertices per grid row, 2 kHalf / kSpacing + 1

std::vector<en::ContactStamp> nearSideContacts() {
  // Off the grid nodes (no vertex near a sphere); the first 3.7 mm from the cut below, the second 8.7 mm.
  std::vector<en::ContactStamp> contacts = {contactAt(Eigen::Vector3d(0.0003, 0.0002, 0.0), 0.4, kRadius, 0.0),
                                            contactAt(Eigen::Vector3d(-0.0047, 0.0031, 0.0), -0.7, kRadius, 1.5)};
  // Tilted b_z: the facing test has work to do against the normals of flatGridNormals.
  contacts[1].frame = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix() * contacts[1].frame;
  return contacts;
}

// Unit normals that wobble with x (the test only needs some to face away from a tilted b_z).
Eigen::Matrix3Xd flatGridNormals(const Eigen::Matrix3Xd& rest) {
  Eigen::Matrix3Xd n(3, rest.cols());
  for (Eigen::Index v = 0; v < rest.cols(); ++v) n.col(v) = Eigen::Vector3d(0.0, 3.0 * std::sin(400.0 * rest(0, v)), 1.0).normalized();
  return n;
}

bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::memcmp(a.data(), b.data(), sizeof(a)) == 0; }
}  // namespace

TEST(StampSurfaceReach, UncutSurfaceIsBitIdenticalToTheWholeBall) {
  const Eigen::Matrix3Xd rest = flatGrid(kHalf, kSpacing);
  ASSERT_EQ(rest.cols(), kGrid * kGrid);
  const Eigen::Matrix3Xd normals = flatGridNormals(rest);
  const std::vector<en::ContactStamp> contacts = nearSideContacts();
  en::StampMapper surface(rest, 0.2, normals, gridTriangles(kGrid));
  en::StampMapper ball(rest, 0.2, normals);
  std::vector<int> referenceIds;
  const Eigen::Matrix3Xd reference = wholeBallReference(surface, normals, contacts, referenceIds);
  for (int pass = 0; pass < 2; ++pass) {  // the second pass reads the cached (filtered) balls
    en::SurfaceEnrichment e, plain;
    surface.map(contacts, e);
    ball.map(contacts, plain);
    ASSERT_EQ(e.vertices, referenceIds);
    ASSERT_EQ(plain.vertices, referenceIds);
    for (std::size_t k = 0; k < e.vertices.size(); ++k) {
      const auto col = static_cast<Eigen::Index>(k);
      EXPECT_TRUE(sameBits(e.displacements.col(col), reference.col(e.vertices[k]))) << e.vertices[k];
      EXPECT_TRUE(sameBits(e.displacements.col(col), plain.displacements.col(col))) << e.vertices[k];
    }
  }
  EXPECT_GT(referenceIds.size(), 1400u);  // both stamps are there (pi (R / h)^2 = 1257 each, union 1487)
  std::vector<int> unfacedIds;
  wholeBallReference(surface, Eigen::Matrix3Xd(), contacts, unfacedIds);
  EXPECT_GT(unfacedIds.size(), referenceIds.size() + 20);  // and the facing test removed some (36)
}

TEST(StampSurfaceReach, StampDoesNotCrossACut) {
  // A slit along the grid column x = 4 mm for |y| < 25 mm: its vertices are duplicated, the copies taking
  // the cells on the +x side; the tips (|y| = 25 mm) stay shared, outside the 2 cm balls, so the surface is
  // one piece but no path inside a ball crosses the slit.
  const int cutColumn = 34, tipRow = 55;  // x = -30 + 34 mm; rows 6..54 have |y| < 25 mm
  const Eigen::Matrix3Xd grid = flatGrid(kHalf, kSpacing);
  std::vector<int> copyOf(grid.cols(), -1);
  Eigen::Matrix3Xd rest(3, grid.cols() + 2 * tipRow - kGrid);
  rest.leftCols(grid.cols()) = grid;
  Eigen::Index next = grid.cols();
  for (int j = kGrid - tipRow; j < tipRow; ++j) {
    copyOf[j * kGrid + cutColumn] = static_cast<int>(next);
    rest.col(next++) = grid.col(j * kGrid + cutColumn);
  }
  ASSERT_EQ(next, rest.cols());
  Eigen::Matrix3Xi triangles = gridTriangles(kGrid);
  for (Eigen::Index f = 0; f < triangles.cols(); ++f) {
    const bool plusSide = triangles.col(f).unaryExpr([](int v) { return v % kGrid; }).minCoeff() == cutColumn;  // cell x in [4, 5] mm
    for (int k = 0; k < 3 && plusSide; ++k)
      if (copyOf[triangles(k, f)] >= 0) triangles(k, f) = copyOf[triangles(k, f)];
  }
  const Eigen::Matrix3Xd normals = flatGridNormals(rest);
  const std::vector<en::ContactStamp> contacts = nearSideContacts();
  en::StampMapper cut(rest, 0.2, normals, triangles);
  en::StampMapper uncut(grid, 0.2, normals.leftCols(grid.cols()), gridTriangles(kGrid));
  en::SurfaceEnrichment e, whole;
  uncut.map(contacts, whole);
  std::vector<int> nearSide;
  bool wholeCrosses = false;
  for (int v : whole.vertices) {
    if (v % kGrid <= cutColumn) nearSide.push_back(v);
    wholeCrosses = wholeCrosses || v % kGrid > cutColumn;
  }
  EXPECT_TRUE(wholeCrosses);  // without the cut the stamps reach past x = 4 mm
  for (int pass = 0; pass < 2; ++pass) {
    cut.map(contacts, e);
    ASSERT_EQ(e.vertices, nearSide);  // nothing on the far lip (copies or beyond), all of the near side
    std::size_t w = 0;
    for (std::size_t k = 0; k < e.vertices.size(); ++k) {
      while (whole.vertices[w] != e.vertices[k]) ++w;
      EXPECT_TRUE(sameBits(e.displacements.col(static_cast<Eigen::Index>(k)), whole.displacements.col(static_cast<Eigen::Index>(w))));
    }
  }
}

TEST(StampSurfaceReach, StampDoesNotGoThroughAThinWall) {
  // A sheet folded back on itself 2 mm above (joined by a strip at x = 30 mm, outside the ball), the
  // normals left out: the facing test cannot help, only the surface path can.
  const Eigen::Matrix3Xd lower = flatGrid(kHalf, kSpacing);
  Eigen::Matrix3Xd upper = lower;
  upper.row(2).setConstant(0.002);
  const int n = static_cast<int>(lower.cols());
  Eigen::Matrix3Xd rest(3, 2 * n);
  rest << lower, upper;
  Eigen::Matrix3Xi strip(3, 2 * (kGrid - 1));
  for (int j = 0; j + 1 < kGrid; ++j) {
    const int a = j * kGrid + kGrid - 1, b = a + kGrid;
    strip.col(2 * j) = Eigen::Vector3i(a, n + a, n + b);
    strip.col(2 * j + 1) = Eigen::Vector3i(a, n + b, b);
  }
  Eigen::Matrix3Xi triangles(3, 2 * gridTriangles(kGrid).cols() + strip.cols());
  triangles << gridTriangles(kGrid), gridTriangles(kGrid, n).colwise().reverse(), strip;
  const std::vector<en::ContactStamp> contacts = {nearSideContacts()[0]};
  en::StampMapper ball(rest, 0.2);
  en::StampMapper surface(rest, 0.2, Eigen::Matrix3Xd(), triangles);
  en::SurfaceEnrichment plain, e;
  ball.map(contacts, plain);
  surface.map(contacts, e);
  ASSERT_GT(plain.vertices.back(), n);  // the 3D ball holds the upper sheet
  ASSERT_FALSE(e.vertices.empty());
  EXPECT_LT(e.vertices.back(), n);  // the surface path does not reach it
  for (std::size_t k = 0; k < e.vertices.size(); ++k) {  // on the lower sheet both agree
    EXPECT_EQ(e.vertices[k], plain.vertices[k]);
    EXPECT_TRUE(sameBits(e.displacements.col(static_cast<Eigen::Index>(k)), plain.displacements.col(static_cast<Eigen::Index>(k))));
  }
  EXPECT_THROW((en::StampMapper{rest, 0.2, Eigen::Matrix3Xd(), Eigen::Matrix3Xi((strip.array() + 2 * n).matrix())}), de::InvalidInputError);
}
