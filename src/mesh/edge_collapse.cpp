#include "deformation_enrichment/mesh/edge_collapse.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_cost.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;
namespace sms = CGAL::Surface_mesh_simplification;

// Same threshold as the degenerate-triangle test of shape_space::DiscreteShells.
constexpr double kDegenerateAreaRatio = 1e-8;

// area / (sum of squared edge lengths) of (p, q, r); equilateral 0.144.
double quality(const Point& p, const Point& q, const Point& r) {
  const double area = 0.5 * std::sqrt(CGAL::cross_product(q - p, r - p).squared_length());
  const double scale = (q - p).squared_length() + (r - q).squared_length() + (p - r).squared_length();
  return scale > 0.0 ? area / scale : 0.0;
}

// Half-edge collapse: the merged vertex is placed at one of the two endpoints, so the kept vertex is a
// fine vertex with its own position. Of the allowed endpoints the one leaving the better worst triangle
// in the star is kept; a collapse that flips a triangle or leaves one below minQuality is refused.
class EndpointPlacement {
public:
  EndpointPlacement(double minQuality, double minStarNormalCosine)
      : minQuality_(minQuality), minStarNormalCosine_(minStarNormalCosine) {}

  template <class Profile>
  boost::optional<Point> operator()(const Profile& profile) const {
    const Mesh& mesh = profile.surface_mesh();
    const bool border0 = mesh.is_border(profile.v0()), border1 = mesh.is_border(profile.v1());
    const bool borderEdge = profile.is_v0_v1_a_border() || profile.is_v1_v0_a_border();
    if (border0 && border1 && !borderEdge) return boost::none;  // would pinch the surface at the outline
    const bool keep0 = !(border1 && !border0), keep1 = !(border0 && !border1);  // keep the outline
    double best = -1.0;
    boost::optional<Point> placement;
    for (int side = 0; side < 2; ++side) {
      if (!(side == 0 ? keep0 : keep1)) continue;
      const Point& candidate = side == 0 ? profile.p0() : profile.p1();
      const double q = worstStarQuality(profile, candidate);
      if (q > best) {
        best = q;
        placement = candidate;
      }
    }
    if (!placement || best < minQuality_) return boost::none;
    return placement;
  }

private:
  // The profile lists the star's triangles, the one or two collapsing ones first; the second vertex of
  // each is the one that moves to the placement.
  template <class Profile>
  double worstStarQuality(const Profile& profile, const Point& placed) const {
    const auto& points = profile.vertex_point_map();
    const auto& triangles = profile.triangles();
    auto it = triangles.begin();
    if (profile.left_face_exists()) ++it;
    if (profile.right_face_exists()) ++it;
    double worst = 1.0;
    std::vector<Vector> normals;
    for (; it != triangles.end(); ++it) {
      const Point& p = get(points, it->v0);
      const Point& moved = get(points, it->v1);
      const Point& r = get(points, it->v2);
      const Vector after = CGAL::cross_product(placed - p, r - p);
      if (CGAL::cross_product(moved - p, r - p) * after <= 0.0) return -1.0;
      worst = std::min(worst, quality(p, placed, r));
      if (minStarNormalCosine_ > -1.0) normals.push_back(after / std::sqrt(after.squared_length()));
    }
    // A fold: two triangles around the kept vertex facing (nearly) opposite ways.
    for (size_t a = 0; a < normals.size(); ++a)
      for (size_t b = a + 1; b < normals.size(); ++b)
        if (normals[a] * normals[b] < minStarNormalCosine_) return -1.0;
    return worst;
  }

  double minQuality_, minStarNormalCosine_;
};

class VertexCountStop {
public:
  explicit VertexCountStop(std::size_t target) : target_(target) {}
  template <class Cost, class Profile>
  bool operator()(const Cost&, const Profile& profile, std::size_t, std::size_t) const {
    return profile.surface_mesh().number_of_vertices() <= target_;
  }

private:
  std::size_t target_;
};

// Tracks which fine vertex survives each collapse (the placement names it by position).
class KeptVertexTracker : public sms::Edge_collapse_visitor_base<Mesh> {
public:
  explicit KeptVertexTracker(Mesh::Property_map<VertexIndex, int> fine) : fine_(fine) {}
  template <class Profile>
  void OnCollapsing(const Profile& profile, const boost::optional<Point>& placement) {
    kept_ = (*placement == profile.p0()) ? fine_[profile.v0()] : fine_[profile.v1()];
  }
  template <class Profile>
  void OnCollapsed(const Profile&, VertexIndex survivor) {
    fine_[survivor] = kept_;
  }

private:
  Mesh::Property_map<VertexIndex, int> fine_;
  int kept_ = -1;
};

/// The triangles as a CGAL surface mesh whose vertices remember their input index ("v:fine").
Mesh surfaceMesh(const Eigen::Matrix3Xi& triangles, const Eigen::Ref<const Eigen::Matrix3Xd>& reference) {
  const Eigen::Index numFine = reference.cols();
  Mesh mesh;
  auto fine = mesh.add_property_map<VertexIndex, int>("v:fine", -1).first;
  std::vector<VertexIndex> handle(size_t(numFine), Mesh::null_vertex());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    std::array<VertexIndex, 3> corners;
    for (int a = 0; a < 3; ++a) {
      const int v = triangles(a, t);
      if (v < 0 || v >= numFine)
        throw InvalidInputError("triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) +
                                " outside [0, " + std::to_string(numFine) + ")");
      if (handle[size_t(v)] == Mesh::null_vertex()) {
        const Eigen::Vector3d x = reference.col(v);
        handle[size_t(v)] = mesh.add_vertex(Point(x.x(), x.y(), x.z()));
        fine[handle[size_t(v)]] = v;
      }
      corners[size_t(a)] = handle[size_t(v)];
    }
    const Point &p = mesh.point(corners[0]), &q = mesh.point(corners[1]), &r = mesh.point(corners[2]);
    const double area = std::sqrt(CGAL::cross_product(q - p, r - p).squared_length());
    const double scale = (q - p).squared_length() + (r - q).squared_length() + (p - r).squared_length();
    if (!(area > 2.0 * kDegenerateAreaRatio * scale))
      throw InvalidInputError("triangle " + std::to_string(t) + " is degenerate");
    if (mesh.add_face(corners[0], corners[1], corners[2]) == Mesh::null_face())
      throw InvalidInputError("triangle " + std::to_string(t) +
                              " makes the mesh non-manifold or inconsistently oriented (an oriented 2-manifold is needed)");
  }
  return mesh;
}

}  // namespace

EdgeCollapse collapseEdges(const Eigen::Matrix3Xi& triangles, const Eigen::Ref<const Eigen::Matrix3Xd>& reference,
                           const EdgeCollapseOptions& options) {
  if (options.targetVertices < 4)
    throw InvalidInputError("target vertex count must be >= 4, got " + std::to_string(options.targetVertices));
  if (!(options.minTriangleQuality >= 0.0 && options.minTriangleQuality < 0.15))
    throw InvalidInputError("minTriangleQuality must lie in [0, 0.15)");
  if (triangles.cols() == 0) throw InvalidInputError("the mesh has no triangles");
  if (!reference.allFinite()) throw InvalidInputError("reference shape is not finite");
  Mesh mesh = surfaceMesh(triangles, reference);
  auto fine = mesh.property_map<VertexIndex, int>("v:fine").first;
  KeptVertexTracker tracker(fine);
  sms::edge_collapse(mesh, VertexCountStop(size_t(options.targetVertices)),
                     CGAL::parameters::get_cost(sms::Edge_length_cost<Mesh>())
                         .get_placement(EndpointPlacement(options.minTriangleQuality, options.minStarNormalCosine))
                         .visitor(tracker));

  EdgeCollapse result;
  for (VertexIndex v : mesh.vertices()) result.keptVertices.push_back(fine[v]);
  std::sort(result.keptVertices.begin(), result.keptVertices.end());
  std::vector<int> keptIndex(size_t(reference.cols()), -1);
  for (size_t k = 0; k < result.keptVertices.size(); ++k) keptIndex[size_t(result.keptVertices[k])] = int(k);
  result.triangles.resize(3, Eigen::Index(mesh.number_of_faces()));
  Eigen::Index t = 0;
  for (Mesh::Face_index f : mesh.faces()) {
    int a = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) result.triangles(a++, t) = keptIndex[size_t(fine[v])];
    ++t;
  }
  return result;
}

TriangleMesh simplifySurface(const TriangleMesh& surface, const EdgeCollapseOptions& options) {
  const EdgeCollapse collapse = collapseEdges(surface.triangles, surface.vertices, options);
  TriangleMesh simplified;
  simplified.vertices.resize(3, Eigen::Index(collapse.keptVertices.size()));
  for (size_t k = 0; k < collapse.keptVertices.size(); ++k)
    simplified.vertices.col(Eigen::Index(k)) = surface.vertices.col(collapse.keptVertices[k]);
  simplified.triangles = collapse.triangles;
  return simplified;
}

}  // namespace deformation_enrichment::mesh
