#pragma once
// Evaluates the contact descriptors of [Seiler14 §4] on one object: site descriptor rho (density moments of
// orders 0..N), stamping frame B, and, given a deformed state, the deformation descriptor mu. Holds what is
// built once per rest mesh: the point sampling with its KD-tree, the boundary surface with its normals
// and a KD-tree over surface vertices (normal look-up at p).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "deformation_enrichment/descriptors/deformation_descriptor.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/descriptors/point_sampling.hpp"
#include "deformation_enrichment/descriptors/stamping_frame.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::descriptors {

struct DescriptorOptions {
  WindowOptions window;           ///< scale h, cut-off, quadrature, search
  int siteOrder = 3;              ///< rho_0..rho_N (paper: N = 3)
  int deformationOrder = 2;       ///< mu_1..mu_N (paper: N = 2)
  double frameTolerance = 1e-3;   ///< see stampingFrame()
  kinematics::MlsOptions mls;
};

struct ContactDescriptor {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward surface normal used for b_z
  hermite::MomentList rhoWorld;   ///< site descriptor in world axes
  StampingFrame frame;
  hermite::MomentList rho;        ///< site descriptor in frame B (compare these with d_rho)
  std::optional<DeformationDescriptor> deformation;  ///< mu in world axes inside
  hermite::MomentList mu;         ///< deformation descriptor in frame B (empty without a deformed state)
};

class DescriptorEvaluator {
public:
  /// Samples = the tet mesh's vertices with lumped volumes; surface = its boundary.
  DescriptorEvaluator(const mesh::TetMesh& rest, const DescriptorOptions& options);
  /// Arbitrary volume samples with a surface for the normals. `surfaceToSample` maps surface vertices to
  /// samples (reported by segmentSites; may be empty, e.g. for an interior grid).
  DescriptorEvaluator(PointSampling sampling, mesh::TriangleMesh surface, std::vector<int> surfaceToSample,
                      const DescriptorOptions& options);

  const DescriptorOptions& options() const { return options_; }
  const PointSampling& sampling() const { return sampling_; }
  const mesh::TriangleMesh& surface() const { return surface_; }
  const Eigen::Matrix3Xd& surfaceNormals() const { return surfaceNormals_; }
  const std::vector<int>& surfaceToSample() const { return surfaceToSample_; }

  /// Outward normal at the surface vertex nearest to p.
  Eigen::Vector3d normalAt(const Eigen::Vector3d& p) const;
  /// Index of the surface vertex nearest to p (throws InvalidInputError for non-finite p).
  int nearestSurfaceVertex(const Eigen::Vector3d& p) const { return surfaceIndex_.nearest(p); }

  /// Site descriptor and frame at p (rest state).
  ContactDescriptor evaluate(const Eigen::Vector3d& p) const;

  /// Site and deformation descriptors at p (a rest-state position) for the deformed positions of all
  /// samples (3 x sampling size). The frame may fall back to the deformation direction.
  ContactDescriptor evaluate(const Eigen::Vector3d& p, const Eigen::Matrix3Xd& deformedSamples) const;

private:
  DescriptorOptions options_;
  PointSampling sampling_;
  mesh::TriangleMesh surface_;
  std::vector<int> surfaceToSample_;
  Eigen::Matrix3Xd surfaceNormals_;
  PointSampling surfaceIndex_;  // surface vertices (zero volumes), only for nearest-vertex look-ups
  std::vector<std::vector<int>> vertexTriangles_;  // surface vertex -> incident triangles  // surface vertices (zero volumes), only for nearest-vertex look-ups
};

}  // namespace deformation_enrichment::descriptors
