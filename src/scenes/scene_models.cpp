#include "deformation_enrichment/scenes/scene_models.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace deformation_enrichment::scenes {
namespace {

using scene_file::FixedRegion;
using scene_file::Procedural;
using scene_file::SceneDescription;

Layering layering(const Eigen::Vector3i& cells, const SceneDescription& d, int skinLayers) {
  Layering l;
  l.cells = cells;
  l.skinThickness = d.skin ? d.skin->thickness : 0.0;
  l.skinLayers = skinLayers;
  return l;
}

Scene proceduralScene(Procedural::Shape shape, const Layering& l) {
  switch (shape) {
    case Procedural::Shape::Slab: {
      SlabOptions o;
      o.layering = l;
      return makeSlab(o);
    }
    case Procedural::Shape::Pillow: {
      PillowOptions o;
      o.layering = l;
      return makePillow(o);
    }
    case Procedural::Shape::Meniscus: {
      MeniscusOptions o;
      o.layering = l;
      return makeMeniscus(o);
    }
  }
  throw InvalidInputError("unknown procedural shape");
}

// The nodes of `mesh` in a box or below a plane (a small tolerance keeps nodes exactly on the plane).
std::vector<int> nodesInRegion(const FixedRegion& region, const mesh::TetMesh& mesh) {
  const double tolerance = 1e-9 * (mesh.vertices.rowwise().maxCoeff() - mesh.vertices.rowwise().minCoeff()).norm();
  std::vector<int> nodes;
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.col(v);
    const bool inside = region.kind == FixedRegion::Kind::Box
                            ? ((x.array() >= region.boxLo.array() - tolerance) && (x.array() <= region.boxHi.array() + tolerance)).all()
                            : x(region.axis) <= region.value + tolerance;
    if (inside) nodes.push_back(static_cast<int>(v));
  }
  return nodes;
}

// At least 3 nodes that do not lie on one line: otherwise the body can still rotate about that line.
void checkHolds(const std::vector<int>& nodes, const mesh::TetMesh& mesh, const std::string& what) {
  if (nodes.size() < 3)
    throw InvalidInputError(what + ": the fixed region holds " + std::to_string(nodes.size()) +
                            " nodes; it needs at least 3 that are not collinear");
  Eigen::Matrix3Xd x(3, static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t k = 0; k < nodes.size(); ++k) x.col(static_cast<Eigen::Index>(k)) = mesh.vertices.col(nodes[k]);
  const Eigen::Matrix3Xd centred = x.colwise() - x.rowwise().mean();
  const Eigen::Vector3d sigma = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (!(sigma(1) > 1e-6 * sigma(0)))
    throw InvalidInputError(what + ": the " + std::to_string(nodes.size()) + " fixed nodes are collinear; the body could rotate about them");
}

// Touchable vertices: the boundary vertices that are not held.
std::vector<int> touchable(const mesh::TetSurface& boundary, const std::vector<int>& fixed) {
  std::vector<char> held(static_cast<std::size_t>(boundary.surfaceToVolume.empty() ? 0 : *std::max_element(
                                                        boundary.surfaceToVolume.begin(), boundary.surfaceToVolume.end()) + 1), 0);
  for (int v : fixed)
    if (v < static_cast<int>(held.size())) held[static_cast<std::size_t>(v)] = 1;
  std::vector<int> top;
  for (int v : boundary.surfaceToVolume)
    if (!held[static_cast<std::size_t>(v)]) top.push_back(v);
  std::sort(top.begin(), top.end());
  return top;
}

double longestEdge(const mesh::TriangleMesh& surface) {
  double longest = 0.0;
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (surface.vertices.col(surface.triangles(k, f)) -
                                   surface.vertices.col(surface.triangles((k + 1) % 3, f))).norm());
  return longest;
}

SceneModels proceduralModels(const SceneDescription& d) {
  const Procedural& p = *d.procedural;
  SceneModels m;
  m.name = d.name;
  m.coarse = proceduralScene(p.shape, layering(p.coarseCells, d, p.coarseSkinLayers));
  m.fine = proceduralScene(p.shape, layering(p.fineCells, d, p.fineSkinLayers));
  for (Scene* s : {&m.coarse, &m.fine}) {
    s->name = d.name;
    if (d.fixed) {
      s->fixedVertices = nodesInRegion(*d.fixed, s->mesh);
      s->topVertices = touchable(mesh::extractSurface(s->mesh), s->fixedVertices);
    }
    checkHolds(s->fixedVertices, s->mesh, d.path + ": " + (s == &m.coarse ? "coarse" : "fine") + " model");
  }
  const mesh::TetSurface boundary = mesh::extractSurface(m.fine.mesh);
  m.surface = boundary.surface;
  m.surfaceToFine = boundary.surfaceToVolume;
  m.fineEdge = longestEdge(m.surface);
  std::ostringstream report;
  report << d.name << ": procedural; coarse " << m.coarse.mesh.numVertices() << " nodes, " << m.coarse.mesh.numTets()
         << " tets; fine " << m.fine.mesh.numVertices() << " nodes, " << m.fine.mesh.numTets() << " tets; display surface "
         << m.surface.numVertices() << " vertices";
  m.report = report.str();
  return m;
}

}  // namespace

SceneModels buildSceneModels(const SceneDescription& scene) {
  if (scene.procedural) return proceduralModels(scene);
  throw InvalidInputError(scene.path + ": scenes with mesh files need the volume readers (not built yet)");
}

}  // namespace deformation_enrichment::scenes
