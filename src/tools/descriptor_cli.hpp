#pragma once
// Command-line options shared by the descriptor tools (de_descriptors, de_segment): the object file and
// the Hermite window, turned into the loaded object the tools evaluate.
#include <CLI/CLI.hpp>
#include <string>

#include "deformation_enrichment/descriptors/evaluator_loading.hpp"

namespace deformation_enrichment::tools {

struct DescriptorCli {
  std::string meshPath, quadrature = "volume";
  int order = 3;
  double scale = 0.0, cutoff = 4.0, spacing = 0.0;

  void addTo(CLI::App& app) {
    app.add_option("--mesh", meshPath, "TetGen M.node (M.ele beside it), or a closed OBJ/PLY surface")->required();
    app.add_option("--scale", scale, "window scale h in metres")->required();
    app.add_option("--order", order, "site descriptor order N (moments 0..N), 1..4")->capture_default_str();
    app.add_option("--quadrature", quadrature, "volume (lumped volumes) or average (paper eq. 8)")->capture_default_str();
    app.add_option("--cutoff", cutoff, "cut-off radius in units of h")->capture_default_str();
    app.add_option("--sample-spacing", spacing, "interior grid spacing for OBJ/PLY input (default h/4)");
  }

  /// Throws IoError / InvalidInputError (see loadDescriptorObject) for bad files or options.
  descriptors::LoadedObject load(descriptors::DescriptorOptions options = {}) const {
    options.window.scale = scale;
    options.window.cutoff = cutoff;
    options.window.quadrature = descriptors::parseQuadrature(quadrature);
    options.siteOrder = order;
    return descriptors::loadDescriptorObject(meshPath, options, spacing);
  }
};

}  // namespace deformation_enrichment::tools
