#pragma once
// One acquired example of [Seiler14 §3]: contact p[i], stamping frame B[i], rest-site and deformation
// descriptors rho[i], mu[i] (both in the frame B[i]) and the stamp Psi[i] (fine - coarse surface
// displacement in frame coordinates, a regular grid over [-R, R]^2 around p[i]), plus how it was made.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::examples {

/// The tool interaction that produced an example (metres).
struct InteractionPattern {
  double indentDepth = 0.0;                      ///< along the inward normal
  Eigen::Vector3d drag = Eigen::Vector3d::Zero();  ///< lateral drag vector (world axes)
};

struct Example {
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();     ///< p[i], rest-state position (m)
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();   ///< B[i], columns b_x b_y b_z
  hermite::MomentList rho;                                ///< site descriptor in frame B[i]
  hermite::MomentList mu;                                 ///< deformation descriptor in frame B[i]
  /// Psi[i]: CV_32FC3, rows x cols nodes spanning [-R, R]^2 (node (0,0) at (-R,-R), column index along
  /// b_x, row index along b_y), displacement (m) in frame coordinates.
  /// A volume stamp (stampLayers >= 2, enrichment/stamp.hpp) stacks its square layers along the rows.
  cv::Mat stamp;
  double stampRadius = 0.0;  ///< R (m)
  int stampLayers = 1;       ///< 1: the paper's surface stamp; >= 2: volume stamp layers over [-R, R] along b_z
  InteractionPattern pattern;
  std::string sceneId;
  int planLine = -1;  ///< 0-based line of the acquisition plan (orders merged shards); -1 unknown
};

/// How a set was made: the scene it was acquired on, every key explicit (materials, resolutions, units,
/// tool, solve, stamp, descriptor options), its mesh and plan files by name with the FNV-1a 64 hash of
/// their bytes.
struct Provenance {
  scene_file::SceneDescription scene;
  std::map<std::string, std::string> fileHashes;  ///< file name -> 16 hex digits
  std::string coarseSimulator;  ///< the simulator the coarse states were recorded from; empty: the package's own
};

/// Set-wide metadata written to the manifest.
struct ExampleSetMetadata {
  std::string scene;                    ///< scene name, e.g. "slab"
  /// Named parameters of sets without provenance (SI units); read for them, not written.
  std::map<std::string, double> material;
  std::string description;
  std::optional<Provenance> provenance;  ///< every set acquired by this version has one
};

struct ExampleSet {
  ExampleSetMetadata metadata;
  std::vector<Example> examples;
};

/// Empty if the example is well formed, otherwise a message naming the first problem: non-finite
/// contact/frame/descriptors/pattern, frame not orthonormal and right-handed (tolerance 1e-6), radius not
/// positive and finite, stamp not CV_32FC3 with at least 2x2 nodes (per layer), non-finite stamp values.
std::string exampleProblem(const Example& example);

/// Throws InvalidInputError with exampleProblem's message (prefixed by `what`) when it is not empty.
void validateExample(const Example& example, const std::string& what = "example");

}  // namespace deformation_enrichment::examples
