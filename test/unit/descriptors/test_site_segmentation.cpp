#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "../top_face.hpp"
#include "descriptor_test_support.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/descriptors/site_segmentation.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;

namespace {
// Keeps the tets whose centroid satisfies `keep`, then drops unused vertices.
template <class Keep>
mesh::TetMesh carve(const mesh::TetMesh& full, Keep keep) {
  std::vector<int> newIndex(full.numVertices(), -1);
  std::vector<Eigen::Vector4i> tets;
  for (Eigen::Index t = 0; t < full.numTets(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += full.vertices.col(full.tets(k, t)) / 4.0;
    if (keep(centroid)) tets.push_back(full.tets.col(t));
  }
  mesh::TetMesh carved;
  int next = 0;
  for (auto& tet : tets)
    for (int k = 0; k < 4; ++k)
      if (newIndex[tet[k]] < 0) newIndex[tet[k]] = next++;
  carved.vertices.resize(3, next);
  for (Eigen::Index v = 0; v < full.numVertices(); ++v)
    if (newIndex[v] >= 0) carved.vertices.col(newIndex[v]) = full.vertices.col(v);
  carved.tets.resize(4, tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) carved.tets(k, t) = newIndex[tets[t][k]];
  return carved;
}

std::set<int> labelsWhere(const DescriptorEvaluator& evaluator, const SiteSegmentation& segmentation,
                          const std::function<bool(const Eigen::Vector3d&)>& where, int* count = nullptr) {
  std::set<int> labels;
  int n = 0;
  for (Eigen::Index v = 0; v < evaluator.surface().numVertices(); ++v)
    if (where(evaluator.surface().vertices.col(v))) {
      labels.insert(segmentation.clusters.labels[v]);
      ++n;
    }
  if (count != nullptr) *count = n;
  return labels;
}

bool disjoint(const std::set<int>& a, const std::set<int>& b) {
  for (int x : a)
    if (b.count(x)) return false;
  return true;
}

std::string show(const std::set<int>& s) {
  std::string out;
  for (int x : s) out += std::to_string(x) + " ";
  return out;
}
}  // namespace

TEST(SiteSegmentation, CubeSeparatesCornersEdgesAndFaces) {
  DescriptorOptions options;
  options.window.scale = 0.15;
  const DescriptorEvaluator evaluator(de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 8),
                                      options);
  // Flat faces hold most vertices, so k-means spends clusters on distances from the edges first (as paper
  // 000 Fig. 6c shows); from 5 clusters on, corners and edges get clusters of their own.
  KMeansOptions kmeans;
  kmeans.clusters = 6;
  const SiteSegmentation segmentation = segmentSites(evaluator, kmeans);
  auto isCorner = [](const Eigen::Vector3d& x) { return (x.cwiseAbs().array() > 0.999).all(); };
  auto isEdgeMiddle = [](const Eigen::Vector3d& x) {
    return (x.cwiseAbs().array() > 0.999).count() == 2 && (x.cwiseAbs().array() < 0.3).count() == 1;
  };
  auto isFaceCentre = [](const Eigen::Vector3d& x) {
    return (x.cwiseAbs().array() > 0.999).count() == 1 && (x.cwiseAbs().array() < 0.3).count() == 2;
  };
  int corners = 0, edges = 0, faces = 0;
  const std::set<int> cornerLabels = labelsWhere(evaluator, segmentation, isCorner, &corners);
  const std::set<int> edgeLabels = labelsWhere(evaluator, segmentation, isEdgeMiddle, &edges);
  const std::set<int> faceLabels = labelsWhere(evaluator, segmentation, isFaceCentre, &faces);
  std::printf("cube: %d corners -> {%s}, %d edge-middle vertices -> {%s}, %d face-centre vertices -> {%s}\n",
              corners, show(cornerLabels).c_str(), edges, show(edgeLabels).c_str(), faces, show(faceLabels).c_str());
  EXPECT_EQ(corners, 8);
  EXPECT_EQ(cornerLabels.size(), 1u) << "all corners alike";
  EXPECT_EQ(edgeLabels.size(), 1u) << "all edge middles alike";
  EXPECT_EQ(faceLabels.size(), 1u) << "all face centres alike";
  EXPECT_TRUE(disjoint(cornerLabels, edgeLabels));
  EXPECT_TRUE(disjoint(cornerLabels, faceLabels));
  EXPECT_TRUE(disjoint(edgeLabels, faceLabels));
  // Deterministic: the same input gives the same labels.
  EXPECT_EQ(segmentSites(evaluator, kmeans).clusters.labels, segmentation.clusters.labels);
}

TEST(SiteSegmentation, SlabSeparatesThinFromThickParts) {
  // A slab 4 x 2 x 1 whose right half is milled down to a quarter of the thickness.
  const mesh::TetMesh full = de_test::uniformBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 2, 1), 8);
  const mesh::TetMesh stepped = carve(full, [](const Eigen::Vector3d& c) { return c.x() < 2.0 || c.z() < 0.25; });
  DescriptorOptions options;
  options.window.scale = 0.2;
  const DescriptorEvaluator evaluator(stepped, options);
  KMeansOptions kmeans;
  kmeans.clusters = 5;
  const SiteSegmentation segmentation = segmentSites(evaluator, kmeans);
  auto thickTop = [](const Eigen::Vector3d& x) {
    return x.z() > 0.999 && x.x() > 0.6 && x.x() < 1.4 && x.y() > 0.6 && x.y() < 1.4;
  };
  auto thinTop = [](const Eigen::Vector3d& x) {
    return std::abs(x.z() - 0.25) < 1e-9 && x.x() > 2.6 && x.x() < 3.4 && x.y() > 0.6 && x.y() < 1.4;
  };
  int thick = 0, thin = 0;
  const std::set<int> thickLabels = labelsWhere(evaluator, segmentation, thickTop, &thick);
  const std::set<int> thinLabels = labelsWhere(evaluator, segmentation, thinTop, &thin);
  std::printf("slab: %d thick-top vertices -> {%s}, %d thin-top vertices -> {%s}\n", thick,
              show(thickLabels).c_str(), thin, show(thinLabels).c_str());
  EXPECT_GT(thick, 10);
  EXPECT_GT(thin, 10);
  EXPECT_EQ(thickLabels.size(), 1u);
  EXPECT_EQ(thinLabels.size(), 1u);
  EXPECT_TRUE(disjoint(thickLabels, thinLabels));
}

TEST(SiteSegmentation, KMeansRecoversSeparatedGroupsAndRejectsBadInput) {
  std::vector<hermite::MomentList> descriptors;
  for (int group = 0; group < 3; ++group)
    for (int k = 0; k < 20; ++k) {
      hermite::MomentList d(0, 1);
      d.values() << group * 10.0 + 0.01 * k, 0.1 * (k % 3), -group, 0.02 * k;
      descriptors.push_back(d);
    }
  KMeansOptions options;
  options.clusters = 3;
  const KMeansResult result = kMeansSites(descriptors, options);
  for (int group = 0; group < 3; ++group)
    for (int k = 1; k < 20; ++k) EXPECT_EQ(result.labels[group * 20 + k], result.labels[group * 20]);
  EXPECT_NE(result.labels[0], result.labels[20]);
  EXPECT_NE(result.labels[20], result.labels[40]);
  EXPECT_NE(result.labels[0], result.labels[40]);
  // The centre of a group is its mean.
  EXPECT_NEAR(result.centres[result.labels[0]].values()[0], 0.095, 1e-12);

  EXPECT_THROW(kMeansSites({}, options), InvalidInputError);
  options.clusters = 61;
  EXPECT_THROW(kMeansSites(descriptors, options), InvalidInputError);
  options.clusters = 2;
  descriptors[5].values()[1] = NAN;
  EXPECT_THROW(kMeansSites(descriptors, options), InvalidInputError);
  descriptors[5] = hermite::MomentList(0, 2);
  EXPECT_THROW(kMeansSites(descriptors, options), InvalidInputError);
}

TEST(SiteSegmentation, AnOpenSurfaceIsSegmentedFromItsVolumeOrAShell) {
  // The top face of a 10 x 10 x 2 cm slab, open: its rim (edges and corners of the slab) differs from its
  // middle whether the material comes from the slab's volume or from a shell under the face.
  const mesh::TetMesh volume = mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                 Eigen::Vector3i(12, 12, 2));
  const mesh::TriangleMesh open = de_test::topFace(mesh::extractSurface(volume).surface, 0.02);
  descriptors::SiteDensityOptions density = descriptors::forWindow({}, 0.006, 0.0);
  for (const mesh::TetMesh* around : {&volume, static_cast<const mesh::TetMesh*>(nullptr)}) {
    const std::vector<int> labels = descriptors::segmentSurface(open, around, 2, 0.006, density);
    ASSERT_EQ(labels.size(), static_cast<std::size_t>(open.numVertices()));
    Eigen::Index centre = 0, corner = 0;
    (open.vertices.colwise() - Eigen::Vector3d(0.0, 0.0, 0.02)).colwise().squaredNorm().minCoeff(&centre);
    (open.vertices.colwise() - Eigen::Vector3d(0.05, 0.05, 0.02)).colwise().squaredNorm().minCoeff(&corner);
    EXPECT_NE(labels[static_cast<std::size_t>(centre)], labels[static_cast<std::size_t>(corner)]) << (around ? "volume" : "shell");
  }
  EXPECT_THROW(descriptors::segmentSurface(open, &volume, 0, 0.006, density), InvalidInputError);
  EXPECT_THROW(descriptors::segmentSurface(open, &volume, static_cast<int>(open.numVertices()) + 1, 0.006, density),
               InvalidInputError);
  EXPECT_THROW(descriptors::segmentSurface(open, &volume, 2, -1.0, density), InvalidInputError);
}
