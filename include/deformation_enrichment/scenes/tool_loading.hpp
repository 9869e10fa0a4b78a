#pragma once
// A rigid tool pressed into or dragged across a scene: the top-surface vertices under the tool tip move
// with it (prescribed, Dirichlet), the support stays at rest, everything else is solved for.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"

namespace deformation_enrichment::scenes {

/// Top vertices whose rest position lies within `radius` of `point` measured in the x-y plane (the tool
/// tip footprint). Throws InvalidInputError if none is found (the tool misses the tissue).
std::vector<int> toolFootprint(const Scene& scene, const Eigen::Vector2d& point, double radius);

/// Tool displacement after `step` of a path that first indents by `depth` along `indentDirection` in
/// `indentSteps` steps, then drags by `dragDistance` along `dragDirection` in `dragSteps` steps
/// (directions are normalised; step 0 is the rest state).
Eigen::Vector3d toolDisplacement(int step, int indentSteps, int dragSteps, const Eigen::Vector3d& indentDirection,
                                 double depth, const Eigen::Vector3d& dragDirection, double dragDistance);

/// Support vertices held at rest plus tool vertices at rest + displacement (tool vertices that are also
/// support vertices stay supported).
elasticity::DirichletConstraints toolConstraints(const Scene& scene, const std::vector<int>& tool,
                                                 const Eigen::Vector3d& displacement);

}  // namespace deformation_enrichment::scenes
