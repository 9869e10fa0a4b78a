#include "deformation_enrichment/elasticity/calculix_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "deformation_enrichment/elasticity/calculix_dat.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/external_program.hpp"
#include "deformation_enrichment/seconds_since.hpp"

namespace deformation_enrichment::elasticity {
namespace {

constexpr const char* kJob = "job";  // ccx -i job reads job.inp and writes job.dat, job.sta, ...

/// The caller's environment with the thread counts replaced.
std::vector<std::string> childEnvironment(int threads) {
  std::vector<std::string> variables;
  for (char** entry = environ; *entry; ++entry) {
    const std::string variable(*entry);
    if (variable.rfind("OMP_NUM_THREADS=", 0) == 0 || variable.rfind("CCX_NPROC_EQUATION_SOLVER=", 0) == 0) continue;
    variables.push_back(variable);
  }
  variables.push_back("OMP_NUM_THREADS=" + std::to_string(threads));
  variables.push_back("CCX_NPROC_EQUATION_SOLVER=" + std::to_string(threads));
  return variables;
}

/// ccx's *ERROR messages (each with the lines after it) or, without any, its last lines: what to show a
/// user once the folder is gone.
std::string logExcerpt(const std::string& log) {
  const std::vector<std::string> lines = nonBlankLines(log);
  std::string errors;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (lines[k].find("*ERROR") == std::string::npos) continue;
    for (std::size_t j = k; j < std::min(lines.size(), k + 3); ++j) errors += (errors.empty() ? "" : " ") + lines[j];
  }
  if (!errors.empty()) return errors;
  std::string tail;
  for (std::size_t k = lines.size() > 3 ? lines.size() - 3 : 0; k < lines.size(); ++k) tail += (tail.empty() ? "" : " ") + lines[k];
  return tail.empty() ? "no output" : tail;
}

bool hasError(const std::string& log) {
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("*ERROR") != std::string::npos) return true;
  return false;
}

}  // namespace

CalculixRun runCalculix(const CalculixModel& model, const CalculixOptions& options) {
  validate(model);
  if (options.threads < 1) throw InvalidInputError("runCalculix: threads must be at least 1");
  TemporaryFolder folder("calculix");
  const std::string deck = folder.file(std::string(kJob) + ".inp"), log = folder.file("ccx.log");
  const std::string dat = folder.file(std::string(kJob) + ".dat");
  {
    std::ofstream out(deck);
    if (!out) throw IoError("cannot write the CalculiX deck " + deck);
    writeCalculixDeck(out, model);
  }
  const auto start = std::chrono::steady_clock::now();
  // ccx writes its scratch files (spooles.out among them) into the working directory: the folder.
  const int status = runProgram({{options.program, "-i", kJob}, log, "calculix-ccx", folder.path().string(), childEnvironment(options.threads)});
  CalculixRun run;
  run.seconds = secondsSince(start);
  // ccx exits 0 after some rejected decks (an unreadable input, for one), so its *ERROR lines count too.
  if (!succeeded(status))
    throw IoError(options.program + " failed on " + deck + " (" + describeStatus(status) + "): " + logExcerpt(log));
  if (hasError(log)) throw IoError(options.program + " rejected " + deck + ": " + logExcerpt(log));
  std::ifstream in(dat);
  if (!in) throw IoError(options.program + " wrote no " + dat + ": " + logExcerpt(log));
  const CalculixDisplacements result = readCalculixDisplacements(in, model.rest.numVertices(), dat);
  if (!(std::abs(result.time - 1.0) <= 1e-6))
    throw IoError(options.program + " stopped at step time " + std::to_string(result.time) + " of 1 in " + dat +
                  " (no convergence): " + logExcerpt(log));
  run.displacements = result.values;
  return run;
}

}  // namespace deformation_enrichment::elasticity
