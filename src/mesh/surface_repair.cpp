#include "deformation_enrichment/mesh/surface_repair.hpp"

#include <algorithm>
#include <array>
#include <iterator>
#include <sstream>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {

// Exact predicates: intersection tests on nearly coplanar triangles must not depend on round-off.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Triangle = std::array<std::size_t, 3>;
namespace pmp = CGAL::Polygon_mesh_processing;

void checkInput(const TriangleMesh& surface) {
  validate(surface, false);  // empty, non-finite, out-of-range: nothing to repair
}

Mesh toMesh(const std::vector<Point>& points, const std::vector<Triangle>& triangles) {
  Mesh mesh;
  pmp::polygon_soup_to_polygon_mesh(points, triangles, mesh);
  return mesh;
}

// The surface as CGAL's polygon soup.
void toSoup(const TriangleMesh& surface, std::vector<Point>& points, std::vector<Triangle>& triangles) {
  for (Eigen::Index v = 0; v < surface.numVertices(); ++v) points.emplace_back(surface.vertices(0, v), surface.vertices(1, v), surface.vertices(2, v));
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f)
    triangles.push_back({static_cast<std::size_t>(surface.triangles(0, f)), static_cast<std::size_t>(surface.triangles(1, f)),
                         static_cast<std::size_t>(surface.triangles(2, f))});
}

TriangleMesh fromMesh(Mesh mesh) {
  mesh.collect_garbage();
  TriangleMesh out;
  out.vertices.resize(3, static_cast<Eigen::Index>(mesh.number_of_vertices()));
  for (Mesh::Vertex_index v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.vertices.col(static_cast<Eigen::Index>(v.idx())) = Eigen::Vector3d(p.x(), p.y(), p.z());
  }
  out.triangles.resize(3, static_cast<Eigen::Index>(mesh.number_of_faces()));
  Eigen::Index f = 0;
  for (Mesh::Face_index face : mesh.faces()) {
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(face), mesh)) out.triangles(k++, f) = static_cast<int>(v.idx());
    ++f;
  }
  return out;
}

Eigen::Index selfIntersections(const Mesh& mesh) {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  pmp::self_intersections(mesh, std::back_inserter(pairs));
  return static_cast<Eigen::Index>(pairs.size());
}

Eigen::Index boundaryEdges(const Mesh& mesh) {
  Eigen::Index count = 0;
  for (Mesh::Halfedge_index h : mesh.halfedges())
    if (mesh.is_border(h)) ++count;
  return count;
}

// Zero-area triangles (repeated or collinear corners; soup repair keeps the collinear ones): exact predicate.
void removeZeroArea(const std::vector<Point>& points, std::vector<Triangle>& triangles) {
  triangles.erase(std::remove_if(triangles.begin(), triangles.end(),
                                 [&](const Triangle& t) { return CGAL::collinear(points[t[0]], points[t[1]], points[t[2]]); }),
                  triangles.end());
}

// Components with less area than `share` of the largest are debris.
Eigen::Index dropDebris(Mesh& mesh, double share) {
  auto component = mesh.add_property_map<Mesh::Face_index, std::size_t>("f:component", 0).first;
  const std::size_t count = pmp::connected_components(mesh, component);
  if (count < 2) return 0;
  std::vector<double> area(count, 0.0);
  for (Mesh::Face_index f : mesh.faces()) area[component[f]] += pmp::face_area(f, mesh);
  const double largest = *std::max_element(area.begin(), area.end());
  std::vector<std::size_t> debris;
  for (std::size_t c = 0; c < count; ++c)
    if (area[c] < share * largest) debris.push_back(c);
  if (!debris.empty()) pmp::remove_connected_components(mesh, debris, component);
  mesh.remove_property_map(component);
  return static_cast<Eigen::Index>(debris.size());
}

Eigen::Index fillHoles(Mesh& mesh) {
  std::vector<Mesh::Halfedge_index> loops;
  pmp::extract_boundary_cycles(mesh, std::back_inserter(loops));
  for (Mesh::Halfedge_index h : loops) {
    std::vector<Mesh::Face_index> added;
    pmp::triangulate_hole(mesh, h, std::back_inserter(added));
  }
  return static_cast<Eigen::Index>(loops.size());
}

// Autorefinement keeps the outer hull of overlapping parts (two intersecting lobes become their union);
// where it cannot make a manifold result, CGAL's local smoothing and hole filling of the intersecting
// region is tried on the original.
void removeSelfIntersections(Mesh& mesh) {
  Mesh refined = mesh;
  bool done = false;
  try {
    done = pmp::experimental::autorefine_and_remove_self_intersections(refined);
  } catch (const std::exception&) {
    done = false;  // CGAL throws on configurations corefinement does not handle; the local repair follows
  }
  if (done && selfIntersections(refined) == 0) {
    mesh = std::move(refined);
    return;
  }
  pmp::experimental::remove_self_intersections(mesh, CGAL::parameters::preserve_genus(false));
}

}  // namespace

Eigen::Index countSelfIntersections(const TriangleMesh& surface) {
  checkInput(surface);
  std::vector<Point> points;
  std::vector<Triangle> triangles;
  toSoup(surface, points, triangles);
  if (!pmp::is_polygon_soup_a_polygon_mesh(triangles))
    throw InvalidInputError("countSelfIntersections: the surface is not an oriented manifold (repairSurface first)");
  return selfIntersections(toMesh(points, triangles));
}

SurfaceRepair repairSurface(const TriangleMesh& surface, const SurfaceRepairOptions& options) {
  checkInput(surface);
  SurfaceRepairReport r;
  std::vector<Point> points;
  std::vector<Triangle> triangles;
  toSoup(surface, points, triangles);
  const std::size_t pointsIn = points.size(), trianglesIn = triangles.size();
  removeZeroArea(points, triangles);
  pmp::repair_polygon_soup(points, triangles);  // merges duplicates, drops duplicate triangles and unused points
  r.removedTriangles = static_cast<Eigen::Index>(trianglesIn - triangles.size());
  const std::size_t pointsRepaired = points.size();
  r.mergedVertices = static_cast<Eigen::Index>(pointsIn - pointsRepaired);
  const std::vector<Triangle> unoriented = triangles;
  pmp::orient_polygon_soup(points, triangles);  // reverses triangles, duplicates the points it must split
  r.splitVertices = static_cast<Eigen::Index>(points.size() - pointsRepaired);
  for (std::size_t f = 0; f < triangles.size(); ++f) r.flippedTriangles += triangles[f] != unoriented[f];
  if (triangles.empty()) throw InvalidInputError("repairSurface: no triangle with area is left");
  if (!pmp::is_polygon_soup_a_polygon_mesh(triangles))  // orientation failed (CGAL would assert below)
    throw InvalidInputError("repairSurface: the triangles cannot be made an oriented manifold");
  Mesh mesh = toMesh(points, triangles);
  r.droppedComponents = dropDebris(mesh, options.minComponentShare);
  r.holesFilled = fillHoles(mesh);
  r.selfIntersections = selfIntersections(mesh);
  if (r.selfIntersections > 0) removeSelfIntersections(mesh);
  r.selfIntersectionsLeft = r.selfIntersections > 0 ? selfIntersections(mesh) : 0;
  r.boundaryEdgesLeft = boundaryEdges(mesh);
  if (r.closedAndSelfIntersectionFree()) {
    r.reoriented = pmp::volume(mesh) < 0.0;  // signed: negative when the surface faces inwards
    pmp::orient_to_bound_a_volume(mesh);
  }
  SurfaceRepair out;
  out.report = r;
  out.surface = r.untouched() ? surface : fromMesh(std::move(mesh));
  return out;
}

std::string describe(const SurfaceRepairReport& r) {
  std::ostringstream s;
  if (r.untouched() && r.closedAndSelfIntersectionFree()) return "clean: nothing to repair";
  s << "repaired: " << r.selfIntersections << " self-intersecting pairs, " << r.holesFilled << " holes";
  if (r.mergedVertices) s << ", " << r.mergedVertices << " duplicate or unused vertices";
  if (r.removedTriangles) s << ", " << r.removedTriangles << " duplicate or zero-area triangles";
  if (r.splitVertices) s << ", " << r.splitVertices << " non-manifold vertices split";
  if (r.flippedTriangles) s << ", " << r.flippedTriangles << " triangles turned to agree with their neighbours";
  if (r.droppedComponents) s << ", " << r.droppedComponents << " debris components dropped";
  if (r.reoriented) s << ", turned outwards";
  if (r.closedAndSelfIntersectionFree())
    s << "; closed, no self-intersection left";
  else
    s << "; left: " << r.selfIntersectionsLeft << " self-intersecting pairs, " << r.boundaryEdgesLeft << " boundary edges";
  return s.str();
}

}  // namespace deformation_enrichment::mesh
