#pragma once
// A tool's command line. Bad input (an unknown option, a missing or out-of-range value) prints CLI11's message
// and exits 1 like every other error of the tools (CLI11_PARSE would return CLI11's own codes: 105 for a value
// out of range); --help prints the help and exits 0.
#include <CLI/CLI.hpp>
#include <optional>

namespace deformation_enrichment::tools {

/// The exit code if the tool should stop here, nothing if it should run.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  return std::nullopt;
}

}  // namespace deformation_enrichment::tools
