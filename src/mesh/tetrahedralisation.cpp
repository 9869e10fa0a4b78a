#include "deformation_enrichment/mesh/tetrahedralisation.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/external_program.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "deformation_enrichment/seconds_since.hpp"

namespace deformation_enrichment::mesh {
namespace {

constexpr int kCoarseAttempts = 6;  // simplification targets up to 1.25^5 = 3x the requested one

/// The intersecting facets tetgen's -d run lists (it numbers facets from 1 in input order), or "".
std::string intersectionReport(const std::string& detectionLog) {
  std::string text;
  for (std::string line : nonBlankLines(detectionLog)) {
    if (line.rfind("Facet #", 0) != 0 && line.rfind("!! Found", 0) != 0) continue;
    if (line.size() > 1 && line.back() == ':') line.erase(line.rfind(" at "));  // "... at triangles:"
    text += (text.empty() ? "" : "; ") + line;
  }
  return text.empty() ? text : text + " (facet #k is triangle k-1)";
}

std::string lastLines(const std::string& log) {
  const std::vector<std::string> lines = nonBlankLines(log);
  std::string text;
  for (size_t k = lines.size() > 4 ? lines.size() - 4 : 0; k < lines.size(); ++k)
    text += (text.empty() ? "" : "; ") + lines[k];
  return text.empty() ? "no message" : text;
}

void requireTetrahedralisable(const TriangleMesh& surface) {
  validate(surface, false);
  const SurfaceReport report = inspectSurface(surface);
  if (!report.closedManifold() || report.duplicateVertices > 0 || report.unusedVertices > 0 ||
      report.degenerateTriangles > 0)
    throw InvalidInputError("tetrahedralise: the surface must be a closed oriented manifold without duplicate or "
                            "unused vertices and zero-area triangles; it has " + describe(report));
}

void writeSmesh(const std::string& path, const TriangleMesh& surface) {
  std::ofstream out(path);
  out << std::setprecision(17) << "# part 1: nodes\n" << surface.numVertices() << " 3 0 0\n";
  for (Eigen::Index v = 0; v < surface.numVertices(); ++v)
    out << v << ' ' << surface.vertices(0, v) << ' ' << surface.vertices(1, v) << ' ' << surface.vertices(2, v) << '\n';
  out << "# part 2: facets\n" << surface.numTriangles() << " 0\n";
  for (Eigen::Index t = 0; t < surface.numTriangles(); ++t)
    out << "3 " << surface.triangles(0, t) << ' ' << surface.triangles(1, t) << ' ' << surface.triangles(2, t) << '\n';
  out << "# part 3: holes\n0\n# part 4: regions\n0\n";
  if (!out) throw IoError("cannot write the tetgen input " + path);
}

std::string switches(const TetrahedraliseOptions& options) {
  std::ostringstream text;
  text << std::setprecision(17) << "-pzQF";  // PLC input, 0-based output, quiet, no .face/.edge files
  if (options.radiusEdgeRatio > 0.0) text << 'q' << options.radiusEdgeRatio;
  if (options.maxVolume > 0.0) text << 'a' << options.maxVolume;
  if (options.keepSurface) text << 'Y';
  return text.str();
}

/// With -Y, tetgen keeps the input points first and in order and the input triangles as the boundary;
/// it writes the points with fewer digits than this package, so they are checked and then set back to
/// the exact input positions.
void checkKeptSurface(TetMesh& mesh, const TriangleMesh& surface) {
  const double scale = (surface.vertices.rowwise().maxCoeff() - surface.vertices.rowwise().minCoeff()).norm();
  if (mesh.numVertices() < surface.numVertices())
    throw NumericalError("tetgen -Y returned fewer nodes than the surface has vertices");
  const double moved = (mesh.vertices.leftCols(surface.numVertices()) - surface.vertices).cwiseAbs().maxCoeff();
  if (!(moved <= 1e-12 * scale))
    throw NumericalError("tetgen -Y moved surface vertices by up to " + std::to_string(moved) + " m");
  mesh.vertices.leftCols(surface.numVertices()) = surface.vertices;
  const TetSurface boundary = extractSurface(mesh);
  bool onSurface = boundary.surface.numTriangles() == surface.numTriangles();
  for (const int v : boundary.surfaceToVolume) onSurface = onSurface && v < surface.numVertices();
  if (!onSurface)
    throw NumericalError("tetgen -Y changed the boundary: " + std::to_string(boundary.surface.numTriangles()) +
                         " boundary triangles for " + std::to_string(surface.numTriangles()) + " input triangles");
}

/// One tetgen run on a checked surface: the result, or why it failed.
struct TetgenRun {
  Tetrahedralisation result;
  std::string failure;            ///< empty on success
  bool selfIntersecting = false;  ///< tetgen's -d run found intersecting facets
};

TetgenRun runTetgen(const TriangleMesh& surface, const TetrahedraliseOptions& options) {
  if (!(options.radiusEdgeRatio >= 0.0) || !(options.maxVolume >= 0.0))
    throw InvalidInputError("tetrahedralise: radiusEdgeRatio and maxVolume must be non-negative");
  TemporaryFolder folder("tetgen");
  const std::string input = folder.file("surface.smesh"), log = folder.file("tetgen.log");
  writeSmesh(input, surface);
  TetgenRun run;
  run.result.command = switches(options);
  const int status = runProgram({{options.program, run.result.command, input}, log, "tetgen"});
  if (!succeeded(status)) {
    // Debian's tetgen aborts without a word on a self-intersecting surface; its -d run lists the
    // intersecting facets.
    const std::string detection = folder.file("tetgen-d.log");
    runProgram({{options.program, "-pdz", input}, detection, "tetgen"});
    const std::string findings = intersectionReport(detection);
    run.selfIntersecting = !findings.empty();
    run.failure = "tetgen " + run.result.command + " failed (" + describeStatus(status) +
                  "): " + (findings.empty() ? lastLines(log) : findings);
    return run;
  }
  run.result.mesh = readTetGen(folder.file("surface.1")).mesh;
  run.result.surfaceVertices = options.keepSurface ? surface.numVertices() : 0;
  if (options.keepSurface) checkKeptSurface(run.result.mesh, surface);
  validate(run.result.mesh);
  return run;
}

/// Simplify, tetrahedralise; where a thin part folds through itself, simplify less.
CoarseVolume simplifiedVolume(const TriangleMesh& closedSurface, const CoarseVolumeOptions& options) {
  // Collapses are checked locally (no flipped or skinny triangle), so a thin part can still fold through
  // itself; tetgen finds that, and a finer simplification is tried instead.
  EdgeCollapseOptions simplification = options.simplification;
  for (int attempt = 0;; ++attempt) {
    TriangleMesh boundary = simplifySurface(closedSurface, simplification);
    TetgenRun run = runTetgen(boundary, options.tetgen);
    if (run.failure.empty()) {
      const Eigen::Index vertices = boundary.numVertices();
      return {std::move(run.result), std::move(boundary), simplification.targetVertices, vertices, 0.0};
    }
    if (!run.selfIntersecting || attempt + 1 == kCoarseAttempts || boundary.numVertices() >= closedSurface.numVertices())
      throw InvalidInputError("coarseVolume: the surface simplified to " + std::to_string(boundary.numVertices()) +
                              " vertices: " + run.failure);
    simplification.targetVertices = simplification.targetVertices * 5 / 4;
  }
}

/// Moves the coarse boundary out by the encloseFraction quantile of the input vertices' distances
/// outside the coarse volume, halving the distance while the moved boundary folds.
void inflate(CoarseVolume& coarse, const TriangleMesh& closedSurface, const CoarseVolumeOptions& options) {
  const double diagonal = (closedSurface.vertices.rowwise().maxCoeff() - closedSurface.vertices.rowwise().minCoeff()).norm();
  const BarycentricEmbedding embedding = embedPoints(coarse.volume.mesh, closedSurface.vertices, diagonal);
  std::vector<double> outside;
  for (Eigen::Index i = 0; i < embedding.outside.size(); ++i)
    if (embedding.outside[i] > 1e-9 * diagonal) outside.push_back(embedding.outside[i]);
  if (outside.empty()) return;
  const size_t k = std::min(outside.size() - 1, size_t(options.encloseFraction * double(outside.size())));
  std::nth_element(outside.begin(), outside.begin() + std::ptrdiff_t(k), outside.end());
  const Eigen::Matrix3Xd normals = vertexNormals(coarse.boundary);
  double distance = outside[k];
  for (int tries = 0; tries < 5; ++tries, distance /= 2.0) {
    TriangleMesh moved = coarse.boundary;
    moved.vertices += distance * normals;
    TetgenRun run = runTetgen(moved, options.tetgen);
    if (run.failure.empty()) {
      coarse.volume = std::move(run.result);
      coarse.boundary = std::move(moved);
      coarse.inflation = distance;
      return;
    }
    if (!run.selfIntersecting) throw InvalidInputError("coarseVolume: inflated boundary: " + run.failure);
  }
}

}  // namespace

Tetrahedralisation tetrahedralise(const TriangleMesh& closedSurface, const TetrahedraliseOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  requireTetrahedralisable(closedSurface);
  TetgenRun run = runTetgen(closedSurface, options);
  if (!run.failure.empty()) throw InvalidInputError("tetrahedralise: " + run.failure);
  run.result.seconds = secondsSince(start);
  return std::move(run.result);
}

CoarseVolume coarseVolume(const TriangleMesh& closedSurface, const CoarseVolumeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  requireTetrahedralisable(closedSurface);
  if (!(options.encloseFraction >= 0.0 && options.encloseFraction <= 1.0))
    throw InvalidInputError("coarseVolume: encloseFraction must lie in [0, 1]");
  CoarseVolume coarse = simplifiedVolume(closedSurface, options);
  if (options.encloseFraction > 0.0) inflate(coarse, closedSurface, options);
  coarse.volume.seconds = secondsSince(start);
  return coarse;
}

}  // namespace deformation_enrichment::mesh
