#include "deformation_enrichment/acquisition/tool_loading.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace deformation_enrichment::acquisition {

std::vector<int> toolFootprint(const scenes::Scene& scene, const Eigen::Vector2d& point, double radius) {
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

elasticity::DirichletConstraints supportConstraints(const scenes::Scene& scene) {
  elasticity::DirichletConstraints constraints;
  for (int v : scene.fixedVertices) constraints.add(v, scene.mesh.vertices.col(v));
  return constraints;
}

elasticity::DirichletConstraints toolConstraints(const scenes::Scene& scene, const std::vector<int>& tool,
                                                 const Eigen::Vector3d& displacement) {
  elasticity::DirichletConstraints constraints = supportConstraints(scene);
  const std::set<int> support(scene.fixedVertices.begin(), scene.fixedVertices.end());
  for (int v : tool)
    if (!support.count(v)) constraints.add(v, scene.mesh.vertices.col(v) + displacement);
  return constraints;
}

elasticity::AnchorSprings toolSprings(const scenes::Scene& scene, const Eigen::Vector3d& centre, double radius,
                                      double stiffnessPerArea) {
  if (!centre.allFinite() || !(radius > 0.0) || !std::isfinite(radius) || !(stiffnessPerArea > 0.0) ||
      !std::isfinite(stiffnessPerArea))
    throw InvalidInputError("toolSprings: centre must be finite, radius and stiffness positive");
  const std::set<int> top(scene.topVertices.begin(), scene.topVertices.end());
  const std::set<int> support(scene.fixedVertices.begin(), scene.fixedVertices.end());
  const mesh::TetSurface surface = mesh::extractSurface(scene.mesh);
  const auto footprint = [&](const Eigen::Vector3d& X) {
    const double s = (X - centre).squaredNorm() / (radius * radius);
    return s < 1.0 ? (1.0 - s) * (1.0 - s) : 0.0;
  };
  std::map<int, double> stiffness;
  for (Eigen::Index f = 0; f < surface.surface.triangles.cols(); ++f) {
    int v[3];
    Eigen::Vector3d X[3];
    bool onTop = true;
    for (int k = 0; k < 3; ++k) {
      v[k] = surface.surfaceToVolume[static_cast<std::size_t>(surface.surface.triangles(k, f))];
      X[k] = scene.mesh.vertices.col(v[k]);
      onTop = onTop && top.count(v[k]);
    }
    if (!onTop) continue;
    const double longest = std::max({(X[1] - X[0]).norm(), (X[2] - X[1]).norm(), (X[0] - X[2]).norm()});
    if ((X[0] - centre).norm() > radius + longest) continue;  // the whole triangle is outside the footprint
    // Midpoint rule on an n x n barycentric subdivision: n^2 pieces of area A / n^2 ("up" and "down").
    const int n = std::max(1, static_cast<int>(std::ceil(4.0 * longest / radius)));
    const double pieceArea = 0.5 * (X[1] - X[0]).cross(X[2] - X[0]).norm() / (n * n);
    double integral[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)
        for (int down = 0; down < (i + j + 1 < n ? 2 : 1); ++down) {
          const double offset = down ? 2.0 / 3.0 : 1.0 / 3.0;
          const double b1 = (i + offset) / n, b2 = (j + offset) / n, b0 = 1.0 - b1 - b2;
          const double w = footprint(b0 * X[0] + b1 * X[1] + b2 * X[2]) * pieceArea;
          integral[0] += w * b0;
          integral[1] += w * b1;
          integral[2] += w * b2;
        }
    for (int k = 0; k < 3; ++k)
      if (integral[k] > 0.0 && !support.count(v[k])) stiffness[v[k]] += stiffnessPerArea * integral[k];
  }
  if (stiffness.empty())
    throw InvalidInputError("toolSprings: the footprint of radius " + std::to_string(radius) + " m at (" +
                            std::to_string(centre.x()) + ", " + std::to_string(centre.y()) + ", " +
                            std::to_string(centre.z()) + ") touches no top surface of scene '" + scene.name + "'");
  elasticity::AnchorSprings springs;
  springs.stiffness.resize(static_cast<Eigen::Index>(stiffness.size()));
  springs.targets.resize(3, static_cast<Eigen::Index>(stiffness.size()));
  for (const auto& [vertex, k] : stiffness) {
    springs.stiffness[static_cast<Eigen::Index>(springs.vertices.size())] = k;
    springs.targets.col(static_cast<Eigen::Index>(springs.vertices.size())) = scene.mesh.vertices.col(vertex);
    springs.vertices.push_back(vertex);
  }
  return springs;
}

}  // namespace deformation_enrichment::acquisition
