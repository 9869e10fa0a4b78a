#pragma once
// Procedural soft-tissue scenes built without external data: a slab, a pillow and a meniscus-like curved
// wedge, each a Kuhn-split hexahedral grid mapped onto the shape, optionally with a thin top skin layer
// (material id 1) over the bulk (material id 0). A stiff thin skin over soft bulk is what wrinkles.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::scenes {

/// Material ids used by the procedural scenes.
enum SceneMaterialId : int { kBulkMaterial = 0, kSkinMaterial = 1 };

struct Scene {
  std::string name;
  mesh::TetMesh mesh;                ///< positively oriented rest mesh (metres)
  Eigen::VectorXi materialId;        ///< per tet: kBulkMaterial or kSkinMaterial
  std::vector<int> fixedVertices;    ///< support (Dirichlet, held at rest)
  std::vector<int> topVertices;      ///< the free top surface, where a tool touches
};

/// Shared layering: `cells` = (cells along the first surface direction, along the second, bulk cells
/// through the thickness); `skinLayers` cells of total thickness `skinThickness` are added on top
/// (skinThickness = 0 disables the skin).
struct Layering {
  Eigen::Vector3i cells{20, 20, 4};
  double skinThickness = 0.001;
  int skinLayers = 1;
};

/// Box [lo, hi]; default 0.10 x 0.10 x 0.02 m with x, y in [-0.05, 0.05], z in [0, 0.02]; bottom fixed.
struct SlabOptions {
  Eigen::Vector3d lo{-0.05, -0.05, 0.0};
  Eigen::Vector3d hi{0.05, 0.05, 0.02};
  Layering layering;
};
Scene makeSlab(const SlabOptions& options = SlabOptions());

/// Rectangular footprint |x| <= halfX, |y| <= halfY whose top bulges from edgeHeight at the rim to
/// height in the middle, z_top = edge + (height - edge) (1 - (x/halfX)^2)(1 - (y/halfY)^2); bottom fixed.
struct PillowOptions {
  double halfX = 0.05, halfY = 0.04;
  double height = 0.03, edgeHeight = 0.008;
  Layering layering;
};
Scene makePillow(const PillowOptions& options = PillowOptions());

/// Meniscus-like curved wedge: an annular sector (radii innerRadius..outerRadius, angles
/// startAngle..endAngle in radians) whose height grows linearly from innerHeight at the inner edge to
/// outerHeight at the rim. cells = (radial, angular, through-thickness). Bottom and outer rim fixed.
struct MeniscusOptions {
  double innerRadius = 0.012, outerRadius = 0.025;
  double startAngle = 0.0, endAngle = 3.0;
  double innerHeight = 0.001, outerHeight = 0.008;
  Layering layering{Eigen::Vector3i(6, 24, 3), 0.0005, 1};
};
Scene makeMeniscus(const MeniscusOptions& options = MeniscusOptions());

/// Indices from `candidates` whose rest position lies within `radius` of `point`.
std::vector<int> verticesNear(const mesh::TetMesh& mesh, const std::vector<int>& candidates,
                              const Eigen::Vector3d& point, double radius);

}  // namespace deformation_enrichment::scenes
