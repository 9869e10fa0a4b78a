#include "deformation_enrichment/scenes/tool_loading.hpp"

#include <set>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::scenes {

std::vector<int> toolFootprint(const Scene& scene, const Eigen::Vector2d& point, double radius) {
  if (!point.allFinite() || !(radius > 0.0) || !std::isfinite(radius))
    throw InvalidInputError("toolFootprint: point must be finite and radius positive");
  std::vector<int> tool;
  for (int v : scene.topVertices)
    if ((scene.mesh.vertices.col(v).head<2>() - point).norm() <= radius) tool.push_back(v);
  if (tool.empty())
    throw InvalidInputError("toolFootprint: no top vertex of scene '" + scene.name + "' within " + std::to_string(radius) +
                            " m of (" + std::to_string(point.x()) + ", " + std::to_string(point.y()) + ")");
  return tool;
}

Eigen::Vector3d toolDisplacement(int step, int indentSteps, int dragSteps, const Eigen::Vector3d& indentDirection,
                                 double depth, const Eigen::Vector3d& dragDirection, double dragDistance) {
  if (indentSteps < 1 || dragSteps < 0 || step < 0 || step > indentSteps + dragSteps)
    throw InvalidInputError("toolDisplacement: step " + std::to_string(step) + " outside the path");
  if (!(indentDirection.norm() > 0.0) || !indentDirection.allFinite() || !std::isfinite(depth) ||
      !std::isfinite(dragDistance) || !dragDirection.allFinite() || (dragSteps > 0 && !(dragDirection.norm() > 0.0)))
    throw InvalidInputError("toolDisplacement: directions must be finite and non-zero, distances finite");
  const double indent = depth * std::min(step, indentSteps) / indentSteps;
  Eigen::Vector3d displacement = indent * indentDirection.normalized();
  if (step > indentSteps) displacement += dragDistance * (step - indentSteps) / dragSteps * dragDirection.normalized();
  return displacement;
}

elasticity::DirichletConstraints toolConstraints(const Scene& scene, const std::vector<int>& tool,
                                                 const Eigen::Vector3d& displacement) {
  elasticity::DirichletConstraints constraints;
  const std::set<int> support(scene.fixedVertices.begin(), scene.fixedVertices.end());
  for (int v : scene.fixedVertices) constraints.add(v, scene.mesh.vertices.col(v));
  for (int v : tool)
    if (!support.count(v)) constraints.add(v, scene.mesh.vertices.col(v) + displacement);
  return constraints;
}

}  // namespace deformation_enrichment::scenes
