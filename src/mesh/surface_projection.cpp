#include "deformation_enrichment/mesh/surface_projection.hpp"

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"

namespace deformation_enrichment::mesh {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 toCgal(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace

struct SurfaceProjector::Impl {
  TriangleMesh surface;
  Eigen::Matrix3Xd normals;
  std::vector<Triangle> triangles;
  Tree tree;
};

SurfaceProjector::SurfaceProjector(const TriangleMesh& surface) : impl_(std::make_unique<Impl>()) {
  validate(surface, false);
  impl_->surface = surface;
  impl_->normals = vertexNormals(surface);
  impl_->triangles.reserve(static_cast<std::size_t>(surface.numTriangles()));
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f)
    impl_->triangles.emplace_back(toCgal(surface.vertices.col(surface.triangles(0, f))),
                                  toCgal(surface.vertices.col(surface.triangles(1, f))),
                                  toCgal(surface.vertices.col(surface.triangles(2, f))));
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.accelerate_distance_queries();
}

SurfaceProjector::~SurfaceProjector() = default;
SurfaceProjector::SurfaceProjector(SurfaceProjector&&) noexcept = default;
SurfaceProjector& SurfaceProjector::operator=(SurfaceProjector&&) noexcept = default;

SurfacePoint SurfaceProjector::project(const Eigen::Vector3d& query) const {
  if (!query.allFinite()) throw InvalidInputError("SurfaceProjector: non-finite query point");
  const auto [closest, primitive] = impl_->tree.closest_point_and_primitive(toCgal(query));
  SurfacePoint s;
  s.triangle = static_cast<Eigen::Index>(primitive - impl_->triangles.cbegin());
  s.point = Eigen::Vector3d(closest.x(), closest.y(), closest.z());
  s.distance = (query - s.point).norm();
  const Eigen::Vector3i t = impl_->surface.triangles.col(s.triangle);
  const Eigen::Vector3d a = impl_->surface.vertices.col(t(0)), b = impl_->surface.vertices.col(t(1)),
                        c = impl_->surface.vertices.col(t(2));
  s.barycentric = barycentricOnTriangle(s.point, a, b, c);
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  Eigen::Vector3d normal = s.barycentric(0) * impl_->normals.col(t(0)) + s.barycentric(1) * impl_->normals.col(t(1)) +
                           s.barycentric(2) * impl_->normals.col(t(2));
  if (!(normal.norm() > 1e-12)) normal = area2 > 0.0 ? n : Eigen::Vector3d::UnitZ();
  s.normal = normal.normalized();
  return s;
}

double SurfaceProjector::distance(const Eigen::Vector3d& query) const {
  if (!query.allFinite()) throw InvalidInputError("SurfaceProjector: non-finite query point");
  return std::sqrt(impl_->tree.squared_distance(toCgal(query)));
}

}  // namespace deformation_enrichment::mesh
