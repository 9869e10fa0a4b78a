#pragma once
// Real deformation sequences for the shape-space tests and benchmarks, and the measures of [Brandt16 Fig. 8]:
//  - the animation clips of the MD2 models of [assimp-testmodels] (frames grouped by their name, "run1" ..
//    "run6" = clip "run"), with Gaussian noise of a given fraction of the bounding-box diagonal;
//  - a closed mesh of [CGAL-data] (extracted from libcgal-demo's data.tar.gz at run time), bent by a known
//    smooth field over the frames, with noise;
//  - temporal roughness (of the shapes' edge lengths, and of the vertex trajectories), the per-vertex
//    Gaussian trajectory filter tuned to a roughness, and the shape distortion (edge lengths, enclosed
//    volume) against the input.
#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CGAL/IO/OFF.h>
#include <CGAL/Simple_cartesian.h>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/md2_reader.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/ghost_mesh.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

namespace deformation_enrichment::shape_space::test {

using Shapes = std::vector<Eigen::VectorXd>;

inline const char* kMd2Directory = "/usr/share/assimp/models/MD2/";
inline const char* kCgalData = "/usr/share/doc/libcgal-demo/data.tar.gz";

struct Clip {
  std::string name;  ///< frame name without its trailing number
  int first = 0, last = 0;
  int frames() const { return last - first + 1; }
};

/// The animation clips of an MD2 file: runs of frames whose names agree up to the trailing number.
inline std::vector<Clip> md2Clips(const mesh::Md2Animation& animation) {
  std::vector<Clip> clips;
  for (int f = 0; f < int(animation.frameNames.size()); ++f) {
    std::string base = animation.frameNames[size_t(f)];
    while (!base.empty() && std::isdigit(static_cast<unsigned char>(base.back()))) base.pop_back();
    if (clips.empty() || clips.back().name != base) clips.push_back({base, f, f});
    else clips.back().last = f;
  }
  return clips;
}

/// Adds independent Gaussian noise of standard deviation fraction x (bounding-box diagonal of the first
/// shape) to every coordinate of every shape.
inline Shapes withNoise(Shapes shapes, double fraction, unsigned seed) {
  const Eigen::Map<const Eigen::Matrix3Xd> first(shapes.front().data(), 3, shapes.front().size() / 3);
  const double diagonal = (first.rowwise().maxCoeff() - first.rowwise().minCoeff()).norm();
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, fraction * diagonal);
  for (Eigen::VectorXd& x : shapes)
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += gauss(rng);
  return shapes;
}

/// The clip's frames, clean (some 8-bit quantised frames have zero-area triangles, so they are not validated).
inline ShapeSequence clipFrames(const mesh::Md2Animation& animation, const Clip& clip) {
  ShapeSequence sequence;
  sequence.triangles = animation.frames[size_t(clip.first)].triangles;
  for (int f = clip.first; f <= clip.last; ++f) sequence.shapes.push_back(flatten(animation.frames[size_t(f)].vertices));
  return sequence;
}

/// The clip's frames as a validated sequence (one topology), noise added.
inline ShapeSequence noisyClip(const mesh::Md2Animation& animation, const Clip& clip, double fraction, unsigned seed) {
  ShapeSequence sequence = clipFrames(animation, clip);
  sequence.shapes = withNoise(std::move(sequence.shapes), fraction, seed);
  validateSequence(sequence, 3);
  return sequence;
}

/// data/meshes/<name>.off of [CGAL-data], extracted into a temporary folder. Throws IoError if the
/// archive or the mesh is missing or the mesh is not a triangle mesh.
inline mesh::TriangleMesh cgalMesh(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "de_cgal_meshes";
  const std::filesystem::path file = folder / "data" / "meshes" / (name + ".off");
  if (!std::filesystem::exists(file)) {
    std::filesystem::create_directories(folder);
    const std::string command = "tar xzf " + std::string(kCgalData) + " -C " + folder.string() + " data/meshes/" + name + ".off";
    if (std::system(command.c_str()) != 0) throw IoError("could not extract " + name + ".off from " + kCgalData);
  }
  std::ifstream in(file);
  std::vector<CGAL::Simple_cartesian<double>::Point_3> points;
  std::vector<std::vector<int>> polygons;
  if (!in || !CGAL::IO::read_OFF(in, points, polygons)) throw IoError("could not read " + file.string());
  mesh::TriangleMesh out;
  out.vertices.resize(3, Eigen::Index(points.size()));
  for (size_t v = 0; v < points.size(); ++v) out.vertices.col(Eigen::Index(v)) << points[v].x(), points[v].y(), points[v].z();
  out.triangles.resize(3, Eigen::Index(polygons.size()));
  for (size_t t = 0; t < polygons.size(); ++t) {
    if (polygons[t].size() != 3) throw IoError(file.string() + " has a polygon that is not a triangle");
    out.triangles.col(Eigen::Index(t)) << polygons[t][0], polygons[t][1], polygons[t][2];
  }
  return out;
}

/// `mesh` simplified to about `vertices` vertices by the ghost mesh's half-edge collapses (ghost_mesh.hpp):
/// a real mesh of the wanted size (e.g. the 26k-vertex armadillo at 5k).
inline mesh::TriangleMesh simplified(const mesh::TriangleMesh& mesh, int vertices) {
  GhostMeshOptions options;
  options.targetVertices = vertices;
  const GhostMesh ghost = ghostMesh(mesh.triangles, flatten(mesh.vertices), options);
  mesh::TriangleMesh out;
  out.vertices.resize(3, ghost.numVertices());
  for (Eigen::Index g = 0; g < ghost.numVertices(); ++g) out.vertices.col(g) = mesh.vertices.col(ghost.fineVertices[size_t(g)]);
  out.triangles = ghost.triangles;
  return out;
}

/// `frames` shapes of `rest` bent about the axis through its centre along its shortest bounding-box side:
/// a point at normalised position u along the longest side turns by angle kappa_k (u - 1/2) on a circle of
/// radius 1 / kappa_k (arc length kept), kappa_k rising smoothly from 0 to maxBend / (longest side).
inline Shapes bentSequence(const mesh::TriangleMesh& rest, int frames, double maxBend) {
  const Eigen::Vector3d lo = rest.vertices.rowwise().minCoeff(), hi = rest.vertices.rowwise().maxCoeff();
  const Eigen::Vector3d centre = 0.5 * (lo + hi), extent = hi - lo;
  int along = 0, across = 0;
  extent.maxCoeff(&along);
  extent.minCoeff(&across);
  const int third = 3 - along - across;
  Shapes shapes;
  for (int k = 0; k < frames; ++k) {
    const double s = 0.5 * (1.0 - std::cos(M_PI * k / (frames - 1)));
    const double kappa = std::max(s * maxBend / extent[along], 1e-9);
    Eigen::Matrix3Xd v = rest.vertices;
    for (Eigen::Index i = 0; i < v.cols(); ++i) {
      const Eigen::Vector3d p = rest.vertices.col(i) - centre;
      const double theta = kappa * p[along], r = 1.0 / kappa - p[across];
      v(along, i) = centre[along] + r * std::sin(theta);
      v(across, i) = centre[across] + 1.0 / kappa - r * std::cos(theta);
      v(third, i) = centre[third] + p[third];
    }
    shapes.push_back(flatten(v));
  }
  return shapes;
}

/// Temporal roughness of the vertex trajectories: summed squared second differences of the positions.
inline double trajectoryRoughness(const Shapes& x) {
  double r = 0.0;
  for (size_t i = 1; i + 1 < x.size(); ++i) r += (x[i - 1] - 2 * x[i] + x[i + 1]).squaredNorm();
  return r;
}

/// Temporal roughness of the shapes themselves: summed squared second differences of every edge length
/// (rigid-invariant, like the shell energy: a rigid motion of a shape or a piece does not count).
inline double intrinsicRoughness(const Shapes& x, const Eigen::Matrix3Xi& triangles) {
  std::vector<Eigen::VectorXd> lengths;
  for (const Eigen::VectorXd& shape : x) {
    Eigen::VectorXd l(3 * triangles.cols());
    for (Eigen::Index t = 0; t < triangles.cols(); ++t)
      for (int k = 0; k < 3; ++k) l[3 * t + k] = (shape.segment<3>(3 * triangles(k, t)) - shape.segment<3>(3 * triangles((k + 1) % 3, t))).norm();
    lengths.push_back(std::move(l));
  }
  return trajectoryRoughness(lengths);
}

/// Gaussian filter of every vertex trajectory (weights renormalised at the sequence ends); the end shapes
/// stay fixed, as in the open flow.
inline Shapes gaussianFilter(const Shapes& x, double sigma) {
  Shapes out = x;
  const int m = int(x.size());
  for (int i = 1; i + 1 < m; ++i) {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(x[0].size());
    double weight = 0.0;
    for (int j = 0; j < m; ++j) {
      const double w = std::exp(-0.5 * (i - j) * (i - j) / (sigma * sigma));
      sum += w * x[size_t(j)];
      weight += w;
    }
    out[size_t(i)] = sum / weight;
  }
  return out;
}

/// The filter width (standard deviation in frames, within [0.05, 20]) that a comparison at equal roughness uses.
struct FilterTuning {
  double sigma = 0.0;
  bool reached = false;  ///< the filter at sigma is as smooth as the target; else sigma is its smoothest width
  double roughness = 0.0;  ///< of the filtered sequence
};

/// The narrowest filter whose output is as smooth as `target` by `roughness` (the first of 41 log-spaced widths
/// that is, refined by bisection against the one before), or, if no width is, the smoothest of them. With the
/// end shapes fixed, the roughness is not monotone in sigma: a 6-frame clip is smoothest near 1.5 frames and
/// 1.5x rougher at 20, where the interior shapes approach their mean.
template <class Roughness>
FilterTuning tuneFilter(const Shapes& x, double target, const Roughness& roughness) {
  constexpr int kWidths = 41;
  constexpr double kNarrowest = 0.05, kWidest = 20.0;
  FilterTuning smoothest;
  double previous = kNarrowest;
  for (int k = 0; k < kWidths; ++k) {
    const double sigma = kNarrowest * std::pow(kWidest / kNarrowest, double(k) / (kWidths - 1));
    const double r = roughness(gaussianFilter(x, sigma));
    if (r <= target) {
      FilterTuning tuning{sigma, true, r};
      double lo = previous;
      for (int it = 0; it < 30 && k > 0; ++it) {
        const double mid = std::sqrt(lo * tuning.sigma);
        const double rMid = roughness(gaussianFilter(x, mid));
        if (rMid <= target) tuning = {mid, true, rMid};
        else lo = mid;
      }
      return tuning;
    }
    if (k == 0 || r < smoothest.roughness) smoothest = {sigma, false, r};
    previous = sigma;
  }
  return smoothest;
}

struct Distortion {
  double edge = 0.0;    ///< mean |l_out / l_in - 1| over all edges of all shapes
  double volume = 0.0;  ///< mean |V_out / V_in - 1| over the shapes (signed volume about the centroid)
};

/// How much each shape's own geometry changed against the input: the smoothing should change the motion,
/// not the shapes ([Brandt16 Fig. 8]: the filtered centaur's head shrinks).
inline Distortion distortion(const Shapes& input, const Shapes& output, const Eigen::Matrix3Xi& triangles) {
  const auto signedVolume = [&](const Eigen::VectorXd& x) {
    const Eigen::Map<const Eigen::Matrix3Xd> v(x.data(), 3, x.size() / 3);
    const Eigen::Vector3d c = v.rowwise().mean();
    double vol = 0.0;
    for (Eigen::Index t = 0; t < triangles.cols(); ++t)
      vol += (v.col(triangles(0, t)) - c).dot((v.col(triangles(1, t)) - c).cross(v.col(triangles(2, t)) - c)) / 6.0;
    return vol;
  };
  Distortion d;
  long edges = 0;
  for (size_t i = 0; i < input.size(); ++i) {
    for (Eigen::Index t = 0; t < triangles.cols(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = triangles(k, t), b = triangles((k + 1) % 3, t);
        const double l0 = (input[i].segment<3>(3 * a) - input[i].segment<3>(3 * b)).norm();
        const double l1 = (output[i].segment<3>(3 * a) - output[i].segment<3>(3 * b)).norm();
        if (!(l0 > 0.0)) continue;  // a collapsed edge of an 8-bit quantised frame
        d.edge += std::abs(l1 / l0 - 1.0);
        ++edges;
      }
    d.volume += std::abs(signedVolume(output[i]) / signedVolume(input[i]) - 1.0);
  }
  d.edge /= double(edges);
  d.volume /= double(input.size());
  return d;
}

/// de_smooth's defaults for a noisy capture: reduced, tau 0.5, restoring force 0.05.
inline FlowOptions captureSmoothing() {
  FlowOptions options;
  options.tau = 0.5;
  options.rho = 0.05;
  options.reduction.reduced = true;
  return options;
}

/// One smoothing run next to the Gaussian filter at the same (intrinsic) roughness.
struct FilterComparison {
  std::vector<double> pathEnergy;  ///< eq. 4 (fine mesh) of the input and after every accepted step
  int accepted = 0, unconverged = 0;
  bool monotone = true;            ///< eq. 4 fell at every accepted step
  double roughnessBefore = 0.0, roughnessAfter = 0.0;  ///< intrinsic, of the input and the flow's result
  double trajectoryBefore = 0.0, trajectoryAfter = 0.0;
  FilterTuning filterTuning;       ///< the filter compared (tuneFilter to the result's roughness)
  /// The flow's step compared with it: the last, if the filter is as smooth as the result; else the first
  /// step as smooth as the smoothest filter (the flow then is at least as smooth as the filter it is held to).
  int comparedStep = 0;
  double comparedRoughness = 0.0;  ///< the flow's at that step
  Distortion flow, filter;         ///< at that step and that width, against the input
  double flowSeconds = 0.0, filterSeconds = 0.0;  ///< the filter's: one pass (the tuning not counted)
  Shapes smoothed;
};

/// Smooths `input` with GOAST's energy (bending for its size) and the given options for `steps` steps (the
/// run ends at a stalled step), then compares it with the filter at equal roughness.
inline FilterComparison compareWithFilter(const ShapeSequence& input, const FlowOptions& options, int steps) {
  FilterComparison c;
  const auto intrinsic = [&](const Shapes& x) { return intrinsicRoughness(x, input.triangles); };
  std::vector<Shapes> iterates;  // after every accepted step
  double untimed = 0.0;          // copying the iterates is the test's, not the flow's
  const auto start = std::chrono::steady_clock::now();
  DiscreteShells energy(input.triangles, input.numVertices(), DiscreteShellsOptions::hyperelasticFor(input.shapes.front()));
  SmoothingFlow flow(energy, input, options);
  c.pathEnergy.push_back(flow.pathEnergy());
  for (int k = 0; k < steps; ++k) {
    const FlowStep step = flow.step();
    if (step.stalled) break;
    ++c.accepted;
    c.unconverged += step.unconvergedAverages;
    c.pathEnergy.push_back(flow.pathEnergy());
    c.monotone = c.monotone && c.pathEnergy.back() < c.pathEnergy[c.pathEnergy.size() - 2];
    const auto copyStart = std::chrono::steady_clock::now();
    iterates.push_back(flow.current().shapes);
    untimed += std::chrono::duration<double>(std::chrono::steady_clock::now() - copyStart).count();
  }
  c.flowSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - untimed;
  c.smoothed = iterates.empty() ? input.shapes : iterates.back();
  c.roughnessBefore = intrinsic(input.shapes);
  c.roughnessAfter = intrinsic(c.smoothed);
  c.trajectoryBefore = trajectoryRoughness(input.shapes);
  c.trajectoryAfter = trajectoryRoughness(c.smoothed);
  c.filterTuning = tuneFilter(input.shapes, c.roughnessAfter, intrinsic);
  const auto filterStart = std::chrono::steady_clock::now();
  const Shapes filtered = gaussianFilter(input.shapes, c.filterTuning.sigma);
  c.filterSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - filterStart).count();
  c.comparedStep = c.accepted;
  c.comparedRoughness = c.roughnessAfter;
  if (!c.filterTuning.reached) {
    for (int k = 1; k <= c.accepted; ++k) {
      const double r = intrinsic(iterates[size_t(k - 1)]);
      if (r <= c.filterTuning.roughness) {
        c.comparedStep = k;
        c.comparedRoughness = r;
        break;
      }
    }
  }
  c.flow = c.comparedStep == 0 ? Distortion{} : distortion(input.shapes, iterates[size_t(c.comparedStep - 1)], input.triangles);
  c.filter = distortion(input.shapes, filtered, input.triangles);
  return c;
}

}  // namespace deformation_enrichment::shape_space::test
