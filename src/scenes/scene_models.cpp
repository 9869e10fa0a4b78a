#include "deformation_enrichment/scenes/scene_models.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetrahedralisation.hpp"
#include "deformation_enrichment/mesh/volume_mesh_io.hpp"
#include "deformation_enrichment/scenes/fine_model.hpp"
#include "deformation_enrichment/seconds_since.hpp"

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
      if (d.fixed->kind == FixedRegion::Kind::Vertices)
        throw InvalidInputError(d.path + ": 'fixed: {vertices: ...}' names nodes of a volume file; a procedural scene has none");
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


// The coarse volume of a file scene with its unused nodes dropped (they would make the stiffness matrix
// singular); fixed node ids of the scene (file order) are mapped to the kept nodes.
mesh::TetMesh compactVolume(const mesh::TetMesh& file, std::vector<int>& fileToNode) {
  fileToNode.assign(static_cast<std::size_t>(file.numVertices()), -1);
  mesh::TetMesh compact;
  std::vector<int> kept;
  for (Eigen::Index t = 0; t < file.numTets(); ++t)
    for (int k = 0; k < 4; ++k) {
      int& id = fileToNode[static_cast<std::size_t>(file.tets(k, t))];
      if (id < 0) {
        id = static_cast<int>(kept.size());
        kept.push_back(file.tets(k, t));
      }
    }
  compact.vertices.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) compact.vertices.col(static_cast<Eigen::Index>(k)) = file.vertices.col(kept[k]);
  compact.tets.resize(4, file.numTets());
  for (Eigen::Index t = 0; t < file.numTets(); ++t)
    for (int k = 0; k < 4; ++k) compact.tets(k, t) = fileToNode[static_cast<std::size_t>(file.tets(k, t))];
  return compact;
}

double meanEdge(const mesh::TetMesh& mesh) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) sum += (mesh.vertices.col(mesh.tets(a, t)) - mesh.vertices.col(mesh.tets(b, t))).norm();
  return sum / (6.0 * static_cast<double>(mesh.numTets()));
}

// Skin: tets whose centroid lies within `thickness` of the display surface.
Eigen::VectorXi skinMaterial(const mesh::TetMesh& mesh, const mesh::SurfaceProjector& surface, double thickness) {
  Eigen::VectorXi material = Eigen::VectorXi::Constant(mesh.numTets(), kBulkMaterial);
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += 0.25 * mesh.vertices.col(mesh.tets(k, t));
    if (surface.distance(centroid) < thickness) material[t] = kSkinMaterial;
  }
  return material;
}

// The fine model's held nodes for a region given by coarse node ids: those within half a mean coarse edge.
std::vector<int> fineNodesNear(const mesh::TetMesh& fine, const mesh::TetMesh& coarse, const std::vector<int>& coarseNodes) {
  const double reach = 0.5 * meanEdge(coarse);
  std::vector<int> nodes;
  for (Eigen::Index v = 0; v < fine.numVertices(); ++v)
    for (int c : coarseNodes)
      if ((fine.vertices.col(v) - coarse.vertices.col(c)).norm() <= reach) {
        nodes.push_back(static_cast<int>(v));
        break;
      }
  return nodes;
}

// The coarse model of a file scene: the user's volume, or the simplified display surface tetrahedralised.
mesh::TetMesh coarseModel(const SceneDescription& d, const DisplaySurface& display, std::vector<int>& fileToNode, std::ostringstream& report) {
  if (!d.volume.empty()) {
    mesh::VolumeMeshFile file = mesh::readVolumeMesh(d.volume);
    report << "; coarse volume " << mesh::describe(file);
    file.mesh.vertices *= d.units;
    return compactVolume(file.mesh, fileToNode);
  }
  if (!display.fillable)
    throw InvalidInputError(d.surface + ": the scene names no 'volume' and the display surface cannot be tetrahedralised for one (" +
                            display.report + ")");
  mesh::CoarseVolumeOptions options;
  options.tetgen.maxVolume = d.coarseMaxVolume;
  const mesh::CoarseVolume coarse = mesh::coarseVolume(display.surface, options);
  report << "; coarse volume tetrahedralised from " << coarse.boundaryVertices << " surface vertices";
  return coarse.volume.mesh;
}

// The scene's fixed region in both models; `fileToNode` maps the volume file's node ids to the coarse model's.
void holdFixedRegion(const SceneDescription& d, const std::vector<int>& fileToNode, SceneModels& m) {
  const scene_file::FixedRegion& region = *d.fixed;
  if (region.kind == FixedRegion::Kind::Vertices) {
    for (int id : region.vertices) {
      if (id >= static_cast<int>(fileToNode.size()))
        throw InvalidInputError(d.path + ": fixed vertex " + std::to_string(id) + " is beyond the volume's " +
                                std::to_string(fileToNode.size()) + " nodes");
      if (fileToNode[static_cast<std::size_t>(id)] < 0)
        throw InvalidInputError(d.path + ": fixed vertex " + std::to_string(id) + " belongs to no tet of the volume");
      m.coarse.fixedVertices.push_back(fileToNode[static_cast<std::size_t>(id)]);
    }
    m.fine.fixedVertices = fineNodesNear(m.fine.mesh, m.coarse.mesh, m.coarse.fixedVertices);
  } else {
    m.coarse.fixedVertices = nodesInRegion(region, m.coarse.mesh);
    m.fine.fixedVertices = nodesInRegion(region, m.fine.mesh);
  }
}

SceneModels fileModels(const SceneDescription& d) {
  const auto start = std::chrono::steady_clock::now();
  std::ostringstream report;
  SceneModels m;
  m.name = d.name;
  const DisplaySurface display = readDisplaySurface(d);
  report << d.name << ": " << display.report;
  std::vector<int> fileToNode;
  m.coarse.mesh = coarseModel(d, display, fileToNode, report);
  FineModel fine = buildFineModel(d, display, m.coarse.mesh);
  m.fine.mesh = std::move(fine.mesh);
  m.surfaceToFine = std::move(fine.surfaceToFine);
  m.surfaceOnFine = std::move(fine.surfaceOnFine);
  m.surface = display.surface;
  // Materials: the skin layer under the display surface, in both models.
  const mesh::SurfaceProjector projector(m.surface);
  for (Scene* s : {&m.coarse, &m.fine}) {
    s->name = d.name;
    s->materialId = d.skin ? skinMaterial(s->mesh, projector, d.skin->thickness)
                           : Eigen::VectorXi::Constant(s->mesh.numTets(), kBulkMaterial);
  }
  holdFixedRegion(d, fileToNode, m);
  for (Scene* s : {&m.coarse, &m.fine}) {
    checkHolds(s->fixedVertices, s->mesh, d.path + ": " + (s == &m.coarse ? "coarse" : "fine") + " model");
    s->topVertices = touchable(mesh::extractSurface(s->mesh), s->fixedVertices);
  }
  m.fineEdge = longestEdge(m.surface);
  report << "; coarse " << m.coarse.mesh.numVertices() << " nodes, " << m.coarse.mesh.numTets() << " tets; fine "
         << m.fine.mesh.numVertices() << " nodes, " << m.fine.mesh.numTets() << " tets (" << fine.report << "); "
         << secondsSince(start) << " s";
  m.report = report.str();
  return m;
}

}  // namespace

SceneModels buildSceneModels(const SceneDescription& scene) {
  return scene.procedural ? proceduralModels(scene) : fileModels(scene);
}

SceneGeometry sceneGeometry(const SceneDescription& scene) {
  SceneGeometry geometry;
  std::ostringstream report;
  if (scene.procedural) {
    const Procedural& p = *scene.procedural;
    geometry.surface = mesh::extractSurface(proceduralScene(p.shape, layering(p.fineCells, scene, p.fineSkinLayers)).mesh).surface;
    geometry.volume = proceduralScene(p.shape, layering(p.coarseCells, scene, p.coarseSkinLayers)).mesh;
    report << "procedural; ";
  } else {
    geometry.surface = mesh::readTriangleMesh(scene.surface);
    geometry.surface.vertices *= scene.units;
    if (!scene.volume.empty()) {
      mesh::VolumeMeshFile file = mesh::readVolumeMesh(scene.volume);
      file.mesh.vertices *= scene.units;
      std::vector<int> fileToNode;
      geometry.volume = compactVolume(file.mesh, fileToNode);
    }
  }
  report << "display surface " << mesh::describe(mesh::inspectSurface(geometry.surface));
  if (geometry.volume) report << "; volume " << geometry.volume->numVertices() << " nodes, " << geometry.volume->numTets() << " tets";
  else report << "; no volume";
  geometry.report = report.str();
  return geometry;
}

}  // namespace deformation_enrichment::scenes
