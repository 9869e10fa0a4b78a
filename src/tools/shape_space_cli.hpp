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
  std::string energyName = "classic";

  void addTo(CLI::App& app, const std::string& ghostHelp, const std::string& symmetricHelp) {
    auto* sub = app.add_option("--subspace", subspace, "PCA subspace dimension (reduced mode, default)")->check(CLI::PositiveNumber);
    app.add_flag("--full", full, "full-space Newton instead of the reduced solver")->excludes(sub);
    app.add_option("--ghost", ghost, ghostHelp)->check(CLI::NonNegativeNumber);
    app.add_flag("--symmetric", symmetric, symmetricHelp);
    app.add_option("--energy", energyName, "classic ([Brandt16 §7]) or hyperelastic (GOAST)")
        ->check(CLI::IsMember({"classic", "hyperelastic"}));
    app.add_flag("--json", json, "print the JSON summary on stdout");
  }

  shape_space::DiscreteShellsParameters parameters() const {
    return energyName == "classic" ? shape_space::DiscreteShellsParameters::classic()
                                   : shape_space::DiscreteShellsParameters::hyperelastic();
  }

  void applyTo(shape_space::ReductionOptions& options) const {
    options.reduced = !full;
    options.subspaceDimension = subspace;
    options.useGhostMesh = ghost > 0;
    if (ghost > 0) options.ghostMesh.targetVertices = ghost;
  }
};

}  // namespace deformation_enrichment::tools
