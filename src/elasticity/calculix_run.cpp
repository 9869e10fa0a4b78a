#include "deformation_enrichment/elasticity/calculix_run.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "deformation_enrichment/elasticity/calculix_dat.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/seconds_since.hpp"

extern char** environ;

namespace deformation_enrichment::elasticity {
namespace {

constexpr const char* kJob = "job";  // ccx -i job reads job.inp and writes job.dat, job.sta, ...

/// A fresh folder under the system's temporary directory, removed with this object.
class TemporaryFolder {
public:
  TemporaryFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "de_calculix_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw IoError("cannot create a temporary folder for ccx in " + pattern);
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ignored;  // a leftover temporary folder is no reason to fail
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
  std::filesystem::path path_;
};

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

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> result;
  for (std::string& s : strings) result.push_back(s.data());
  result.push_back(nullptr);
  return result;
}

/// Runs `program -i job` inside `folder` (ccx writes its scratch files, spooles.out among them, into the
/// working directory) with stdout and stderr in `log`; returns the wait status.
int runInFolder(const CalculixOptions& options, const TemporaryFolder& folder, const std::string& log) {
  std::vector<std::string> arguments{options.program, "-i", kJob};
  std::vector<std::string> environment = childEnvironment(options.threads);
  std::vector<char*> argv = pointers(arguments), envp = pointers(environment);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, folder.path().c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int failed = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (failed != 0)
    throw IoError("cannot run '" + options.program + "' (" + std::strerror(failed) +
                  "); Debian's calculix-ccx package provides it (scripts/install-deps)");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw IoError("lost the '" + options.program + "' process: " + std::strerror(errno));
  return status;
}

std::string describeStatus(int status) {
  if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

/// ccx's *ERROR messages (each with the lines after it) or, without any, its last lines: what to show a
/// user once the folder is gone.
std::string logExcerpt(const std::string& log) {
  std::ifstream in(log);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(' ') != std::string::npos) lines.push_back(line.substr(line.find_first_not_of(' ')));
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
  TemporaryFolder folder;
  const std::string deck = folder.file(std::string(kJob) + ".inp"), log = folder.file("ccx.log");
  const std::string dat = folder.file(std::string(kJob) + ".dat");
  {
    std::ofstream out(deck);
    if (!out) throw IoError("cannot write the CalculiX deck " + deck);
    writeCalculixDeck(out, model);
  }
  const auto start = std::chrono::steady_clock::now();
  const int status = runInFolder(options, folder, log);
  CalculixRun run;
  run.seconds = secondsSince(start);
  // ccx exits 0 after some rejected decks (an unreadable input, for one), so its *ERROR lines count too.
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
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
