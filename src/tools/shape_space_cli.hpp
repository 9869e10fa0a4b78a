#pragma once
// Command-line options shared by the shape-space tools (de_smooth, de_geodesic): reduced or full space,
// subspace size, ghost mesh, averaging and the Discrete Shells variant.
#include <CLI/CLI.hpp>
#include <string>

#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"

namespace deformation_enrichment::tools {

struct ShapeSpaceCli {
  int subspace = 16;
  int ghost = 0;  ///< ghost mesh vertices, 0 = off (each tool sets its default)
  bool full = false, symmetric = false, json = false;
  std::string energyName = "hyperelastic";

  void addTo(CLI::App& app, const std::string& ghostHelp, const std::string& symmetricHelp) {
    auto* sub = app.add_option("--subspace", subspace, "PCA subspace dimension (reduced mode, the default; capped by the shapes' own directions)")
                    ->check(CLI::PositiveNumber)
                    ->capture_default_str();
    app.add_flag("--full", full, "full-space Newton instead of the reduced solver")->excludes(sub);
    app.add_option("--ghost", ghost, ghostHelp)->check(CLI::NonNegativeNumber);
    app.add_flag("--symmetric", symmetric, symmetricHelp);
    app.add_option("--energy", energyName,
                   "hyperelastic (GOAST's, bending scaled to the mesh size; default) or classic ([Brandt16 §7]; "
                   "no barrier against collapsing triangles, docs/design.md §10)")
        ->check(CLI::IsMember({"classic", "hyperelastic"}));
    app.add_flag("--json", json, "print the JSON summary on stdout");
  }

  /// The energy's parameters for shapes whose first one is `reference` (flat 3V).
  shape_space::DiscreteShellsOptions parameters(const Eigen::VectorXd& reference) const {
    if (energyName == "classic") return shape_space::DiscreteShellsOptions::classic();
    return shape_space::DiscreteShellsOptions::hyperelasticFor(reference);
  }

  void applyTo(shape_space::ReductionOptions& options) const {
    options.reduced = !full;
    options.subspaceDimension = subspace;
    options.useGhostMesh = ghost > 0;
    if (ghost > 0) options.ghostMesh.targetVertices = ghost;
  }
};

}  // namespace deformation_enrichment::tools
