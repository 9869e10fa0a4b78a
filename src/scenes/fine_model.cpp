#include "deformation_enrichment/scenes/fine_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"
#include "deformation_enrichment/mesh/surface_repair.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_refinement.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetrahedralisation.hpp"

namespace deformation_enrichment::scenes {
namespace {

bool needsRepair(const mesh::SurfaceReport& r) {
  return !r.closedManifold() || r.duplicateVertices > 0 || r.unusedVertices > 0 || r.degenerateTriangles > 0;
}

// Per display vertex, the fine boundary node nearest to its projection on the fine boundary.
std::vector<int> nearestBoundaryNodes(const mesh::TetMesh& fine, const Eigen::Matrix3Xd& points) {
  const mesh::TetSurface boundary = mesh::extractSurface(fine);
  const mesh::SurfaceProjector projector(boundary.surface);
  std::vector<int> nodes(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index v = 0; v < points.cols(); ++v) {
    const mesh::SurfacePoint s = projector.project(points.col(v));
    Eigen::Index corner = 0;
    s.barycentric.maxCoeff(&corner);
    nodes[static_cast<std::size_t>(v)] = boundary.surfaceToVolume[static_cast<std::size_t>(boundary.surface.triangles(corner, s.triangle))];
  }
  return nodes;
}

FineModel refinedCoarse(const scene_file::SceneDescription& scene, const DisplaySurface& display, const mesh::TetMesh& coarse,
                        double maxVolume, const std::string& why) {
  FineModel fine;
  const int levels = mesh::refinementLevels(coarse, maxVolume);
  fine.mesh = mesh::refineTets(coarse, levels);
  fine.surfaceOnFine = mesh::embedPoints(fine.mesh, display.surface.vertices, scene.maxOutside);
  fine.surfaceToFine = nearestBoundaryNodes(fine.mesh, display.surface.vertices);
  fine.report = "fine model: the coarse volume refined " + std::to_string(levels) + " times (1:8), since " + why +
                "; display surface embedded (" + mesh::describe(fine.surfaceOnFine->report, display.surface.numVertices()) + ")";
  return fine;
}

}  // namespace

DisplaySurface readDisplaySurface(const scene_file::SceneDescription& scene) {
  DisplaySurface display;
  display.surface = mesh::readTriangleMesh(scene.surface);
  display.surface.vertices *= scene.units;
  const mesh::SurfaceReport inspected = mesh::inspectSurface(display.surface);
  display.report = "surface " + mesh::describe(inspected);
  if (!needsRepair(inspected)) {
    const Eigen::Index crossings = mesh::countSelfIntersections(display.surface);
    if (crossings == 0) {
      display.fillable = true;
      return display;
    }
  }
  try {
    const mesh::SurfaceRepair repair = mesh::repairSurface(display.surface);
    display.surface = repair.surface;
    display.fillable = repair.report.closedAndSelfIntersectionFree();
    display.report += "; " + mesh::describe(repair.report);
  } catch (const InvalidInputError& e) {  // the file's surface stays the display surface, embedded in the fallback
    display.report += std::string("; not repairable: ") + e.what();
  }
  return display;
}

double defaultFineMaxVolume(const mesh::TriangleMesh& surface) {
  std::vector<double> edges;
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f)
    for (int k = 0; k < 3; ++k)
      edges.push_back((surface.vertices.col(surface.triangles(k, f)) - surface.vertices.col(surface.triangles((k + 1) % 3, f))).norm());
  if (edges.empty()) throw InvalidInputError("defaultFineMaxVolume: the surface has no triangle");
  std::nth_element(edges.begin(), edges.begin() + static_cast<long>(edges.size() / 2), edges.end());
  const double edge = edges[edges.size() / 2];
  return edge * edge * edge / (6.0 * std::sqrt(2.0));  // regular tet of edge `edge`
}

FineModel buildFineModel(const scene_file::SceneDescription& scene, const DisplaySurface& display, const mesh::TetMesh& coarse) {
  const double maxVolume = scene.fineMaxVolume > 0.0 ? scene.fineMaxVolume : defaultFineMaxVolume(display.surface);
  std::ostringstream volume;
  volume << "fine max_volume " << maxVolume << " m^3"
         << (scene.fineMaxVolume > 0.0 ? "" : " (default: a regular tet with the display surface's median edge)") << "; ";
  std::string why = "the display surface could not be made closed and free of self-intersections";
  if (display.fillable) {
    try {
      mesh::TetrahedraliseOptions options;
      options.maxVolume = maxVolume;
      const mesh::Tetrahedralisation conforming = mesh::tetrahedralise(display.surface, options);
      FineModel fine;
      fine.mesh = conforming.mesh;
      fine.surfaceToFine.resize(static_cast<std::size_t>(display.surface.numVertices()));
      for (std::size_t v = 0; v < fine.surfaceToFine.size(); ++v) fine.surfaceToFine[v] = static_cast<int>(v);  // -Y keeps them first
      fine.report = volume.str() + "tetgen " + conforming.command;
      return fine;
    } catch (const InvalidInputError& e) {
      why = std::string("tetgen refused the surface (") + e.what() + ")";
    }
  }
  try {
    FineModel fine = refinedCoarse(scene, display, coarse, maxVolume, why);
    fine.report = volume.str() + fine.report;
    return fine;
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(scene.surface + ": no fine model: " + why + ", and the refined coarse volume cannot hold the display surface: " +
                            e.what());
  }
}

}  // namespace deformation_enrichment::scenes
