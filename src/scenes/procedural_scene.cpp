#include "deformation_enrichment/scenes/procedural_scene.hpp"

#include <cmath>
#include <functional>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

namespace deformation_enrichment::scenes {
namespace {

void checkLayering(const Layering& layering, double height, const std::string& scene) {
  if ((layering.cells.array() < 1).any()) throw InvalidInputError(scene + ": needs at least one cell per axis");
  if (!std::isfinite(layering.skinThickness) || layering.skinThickness < 0.0)
    throw InvalidInputError(scene + ": skin thickness must be finite and non-negative");
  if (layering.skinThickness > 0.0 && layering.skinLayers < 1)
    throw InvalidInputError(scene + ": a skin needs at least one cell layer");
  if (!(layering.skinThickness < height))
    throw InvalidInputError(scene + ": skin thickness must be smaller than the thinnest part of the shape");
}

/// Grid (i, j, k) with i < nx+1, j < ny+1, k < nz+1 (nz = bulk + skin layers), vertices placed by `place`
/// from (s, t, k) where s, t in [0, 1] and k the layer index. Tets entirely in the top skin layers get
/// kSkinMaterial; vertices with k = 0 are the bottom, k = nz the top.
Scene layeredGrid(const std::string& name, const Layering& layering,
                  const std::function<Eigen::Vector3d(double s, double t, int k)>& place) {
  const int nx = layering.cells[0], ny = layering.cells[1];
  const int bulk = layering.cells[2];
  const int skin = layering.skinThickness > 0.0 ? layering.skinLayers : 0;
  const int nz = bulk + skin;
  Scene scene;
  scene.name = name;
  scene.mesh = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(nx, ny, nz), Eigen::Vector3i(nx, ny, nz));
  const int vx = nx + 1, vy = ny + 1;
  Eigen::VectorXi layer(scene.mesh.numVertices());
  for (Eigen::Index v = 0; v < scene.mesh.numVertices(); ++v) {
    const int i = static_cast<int>(v % vx), j = static_cast<int>((v / vx) % vy), k = static_cast<int>(v / (vx * vy));
    layer[v] = k;
    scene.mesh.vertices.col(v) = place(static_cast<double>(i) / nx, static_cast<double>(j) / ny, k);
    if (k == 0) scene.fixedVertices.push_back(static_cast<int>(v));
    if (k == nz) scene.topVertices.push_back(static_cast<int>(v));
  }
  scene.materialId = Eigen::VectorXi::Constant(scene.mesh.numTets(), kBulkMaterial);
  for (Eigen::Index t = 0; t < scene.mesh.numTets(); ++t) {
    bool inSkin = skin > 0;
    for (int c = 0; c < 4; ++c) inSkin = inSkin && layer[scene.mesh.tets(c, t)] >= bulk;
    if (inSkin) scene.materialId[t] = kSkinMaterial;
  }
  // The maps below have positive Jacobians, but a coarse grid on a curved map could still fold a tet.
  mesh::validate(scene.mesh);
  return scene;
}

/// Height of layer k when the bulk fills [0, total - skin] and the skin fills [total - skin, total].
double layerHeight(int k, double total, const Layering& layering) {
  const int bulk = layering.cells[2];
  const double skin = layering.skinThickness;
  if (k <= bulk) return (total - skin) * k / bulk;
  return total - skin + skin * (k - bulk) / layering.skinLayers;
}

}  // namespace

Scene makeSlab(const SlabOptions& options) {
  const Eigen::Vector3d size = options.hi - options.lo;
  if (!size.allFinite() || (size.array() <= 0.0).any()) throw InvalidInputError("slab: hi must exceed lo on every axis");
  checkLayering(options.layering, size.z(), "slab");
  return layeredGrid("slab", options.layering, [&](double s, double t, int k) {
    return Eigen::Vector3d(options.lo.x() + s * size.x(), options.lo.y() + t * size.y(),
                           options.lo.z() + layerHeight(k, size.z(), options.layering));
  });
}

Scene makePillow(const PillowOptions& o) {
  if (!(o.halfX > 0.0 && o.halfY > 0.0 && o.edgeHeight > 0.0 && o.height >= o.edgeHeight && std::isfinite(o.height)))
    throw InvalidInputError("pillow: needs positive half sizes and 0 < edgeHeight <= height");
  checkLayering(o.layering, o.edgeHeight, "pillow");
  return layeredGrid("pillow", o.layering, [&](double s, double t, int k) {
    const double x = (2.0 * s - 1.0) * o.halfX, y = (2.0 * t - 1.0) * o.halfY;
    const double bulge = (1.0 - (2.0 * s - 1.0) * (2.0 * s - 1.0)) * (1.0 - (2.0 * t - 1.0) * (2.0 * t - 1.0));
    const double top = o.edgeHeight + (o.height - o.edgeHeight) * bulge;
    return Eigen::Vector3d(x, y, layerHeight(k, top, o.layering));
  });
}

Scene makeMeniscus(const MeniscusOptions& o) {
  if (!(o.innerRadius > 0.0 && o.outerRadius > o.innerRadius && o.endAngle > o.startAngle &&
        o.endAngle - o.startAngle < 2.0 * M_PI && o.innerHeight > 0.0 && o.outerHeight >= o.innerHeight &&
        std::isfinite(o.outerRadius) && std::isfinite(o.outerHeight)))
    throw InvalidInputError("meniscus: needs 0 < innerRadius < outerRadius, an angle span in (0, 2 pi), "
                            "and 0 < innerHeight <= outerHeight");
  checkLayering(o.layering, o.innerHeight, "meniscus");
  Scene scene = layeredGrid("meniscus", o.layering, [&](double s, double t, int k) {
    const double radius = o.innerRadius + s * (o.outerRadius - o.innerRadius);
    const double angle = o.startAngle + t * (o.endAngle - o.startAngle);
    const double top = o.innerHeight + s * (o.outerHeight - o.innerHeight);
    return Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle), layerHeight(k, top, o.layering));
  });
  // The rim is attached to the joint capsule: hold the outer radial face too (s = 1, i = cells.x).
  const int vx = o.layering.cells[0] + 1;
  for (Eigen::Index v = 0; v < scene.mesh.numVertices(); ++v)
    if (v % vx == vx - 1 && scene.mesh.vertices(2, v) > 0.0) scene.fixedVertices.push_back(static_cast<int>(v));
  std::vector<int> top;
  for (int v : scene.topVertices)
    if (v % vx != vx - 1) top.push_back(v);
  scene.topVertices = top;
  return scene;
}

std::vector<int> verticesNear(const mesh::TetMesh& mesh, const std::vector<int>& candidates,
                              const Eigen::Vector3d& point, double radius) {
  if (!point.allFinite() || !(radius >= 0.0)) throw InvalidInputError("verticesNear: point and radius must be finite");
  std::vector<int> near;
  for (int v : candidates) {
    if (v < 0 || v >= mesh.numVertices()) throw InvalidInputError("verticesNear: candidate index out of range");
    if ((mesh.vertices.col(v) - point).norm() <= radius) near.push_back(v);
  }
  return near;
}

}  // namespace deformation_enrichment::scenes
