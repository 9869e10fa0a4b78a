#pragma once
// The nearest point of a triangle surface to a query point, with its triangle, barycentric coordinates and
// the interpolated vertex normal there: contacts and plan points "where they are" on the surface, and the
// distance of volume points to the surface (skin layers). CGAL's AABB tree does the search.
#include <Eigen/Core>
#include <memory>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct SurfacePoint {
  Eigen::Index triangle = -1;
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  ///< of point in `triangle` (>= 0, sum 1)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();      ///< unit, from the area-weighted vertex normals
  double distance = 0.0;                                  ///< |query - point|
};

class SurfaceProjector {
public:
  /// Throws InvalidInputError for an invalid mesh (validate(mesh, false)).
  explicit SurfaceProjector(const TriangleMesh& surface);
  ~SurfaceProjector();
  SurfaceProjector(SurfaceProjector&&) noexcept;
  SurfaceProjector& operator=(SurfaceProjector&&) noexcept;

  /// Nearest surface point of `query`. Throws InvalidInputError for a non-finite query.
  SurfacePoint project(const Eigen::Vector3d& query) const;
  /// Distance of `query` to the surface.
  double distance(const Eigen::Vector3d& query) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deformation_enrichment::mesh
