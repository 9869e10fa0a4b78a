#pragma once
// A rigid tool pressed into or dragged across a scene, the support held at rest, everything else solved
// for. Two tool models: Dirichlet (the top vertices under the tip move with it) and a penalty tool
// (springs on the top vertices whose stiffness integrates a smooth footprint over the top surface, so
// the load varies smoothly with where the tool is, whatever the mesh resolution).
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"

namespace deformation_enrichment::acquisition {

/// Top vertices whose rest position lies within `radius` of `point` measured in the x-y plane (the tool
/// tip footprint). Throws InvalidInputError if none is found (the tool misses the tissue).
std::vector<int> toolFootprint(const scenes::Scene& scene, const Eigen::Vector2d& point, double radius);

/// Tool displacement after `step` of a path that first indents by `depth` along `indentDirection` in
/// `indentSteps` steps, then drags by `dragDistance` along `dragDirection` in `dragSteps` steps
/// (directions are normalised; step 0 is the rest state).
Eigen::Vector3d toolDisplacement(int step, int indentSteps, int dragSteps, const Eigen::Vector3d& indentDirection,
                                 double depth, const Eigen::Vector3d& dragDirection, double dragDistance);

/// Support vertices held at rest plus tool vertices at rest + displacement (tool vertices that are also
/// support vertices stay supported).
elasticity::DirichletConstraints toolConstraints(const scenes::Scene& scene, const std::vector<int>& tool,
                                                 const Eigen::Vector3d& displacement);

/// Support held at rest (the Dirichlet part of a penalty-tool load).
elasticity::DirichletConstraints supportConstraints(const scenes::Scene& scene);

/// Penalty tool at rest: springs on the top vertices, targets at their rest positions (add the tool
/// displacement to the targets to move the tool). k_v = stiffnessPerArea * integral over the top surface
/// of w(|X - centre|) phi_v(X) dA, with phi_v the linear hat function of v and the footprint
/// w(r) = (1 - (r/radius)^2)^2 for r < radius (total stiffness stiffnessPerArea * pi radius^2 / 3).
/// Integrated on each top triangle subdivided to pieces of at most radius / 4. Support vertices get no
/// spring. Throws InvalidInputError for a non-finite centre, non-positive radius or stiffness, or a
/// footprint that touches no top triangle.
elasticity::AnchorSprings toolSprings(const scenes::Scene& scene, const Eigen::Vector3d& centre, double radius,
                                      double stiffnessPerArea);

}  // namespace deformation_enrichment::acquisition
