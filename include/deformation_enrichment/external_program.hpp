#pragma once
// An outside program run as a separate process (tetgen, CalculiX's ccx: AGPL and GPL tools the package runs,
// never links), in a temporary folder, its output captured in a log.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"

extern char** environ;

namespace deformation_enrichment {

/// A fresh folder under the system's temporary directory, removed with this object.
class TemporaryFolder {
public:
  /// `purpose` names the folder (de_<purpose>_XXXXXX) and the error if it cannot be made.
  explicit TemporaryFolder(const std::string& purpose) {
    std::string pattern = (std::filesystem::temp_directory_path() / ("de_" + purpose + "_XXXXXX")).string();
    if (!::mkdtemp(pattern.data())) throw IoError("cannot create a temporary folder for " + purpose + " in " + pattern);
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

struct ProgramRun {
  std::vector<std::string> arguments;  ///< the program first, looked up on PATH
  std::string log;                     ///< stdout and stderr go here (truncated first)
  std::string package;                 ///< the Debian package that provides the program, named when it cannot start
  std::string workingDirectory = "";   ///< empty: the caller's
  std::optional<std::vector<std::string>> environment = std::nullopt;  ///< NAME=value entries; none: the caller's
};

/// Runs the program to its end and returns its wait status. Throws IoError when it cannot be started.
inline int runProgram(const ProgramRun& run) {
  const auto pointers = [](const std::vector<std::string>& strings) {
    std::vector<char*> result;
    for (const std::string& s : strings) result.push_back(const_cast<char*>(s.c_str()));
    result.push_back(nullptr);
    return result;
  };
  const std::vector<char*> argv = pointers(run.arguments);
  const std::vector<char*> envp = run.environment ? pointers(*run.environment) : std::vector<char*>();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!run.workingDirectory.empty()) posix_spawn_file_actions_addchdir_np(&actions, run.workingDirectory.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, run.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int failed = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), run.environment ? envp.data() : environ);
  posix_spawn_file_actions_destroy(&actions);
  if (failed != 0)
    throw IoError("cannot run '" + run.arguments[0] + "' (" + std::strerror(failed) + "); Debian's " + run.package +
                  " package provides it (scripts/install-deps)");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw IoError("lost the '" + run.arguments[0] + "' process: " + std::strerror(errno));
  return status;
}

/// The program exited, with code 0.
inline bool succeeded(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }

/// "exit code N", "signal N": for a message.
inline std::string describeStatus(int status) {
  if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

/// The file's lines that hold more than spaces, without their leading spaces (a log to quote).
inline std::vector<std::string> nonBlankLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(' ') != std::string::npos) lines.push_back(line.substr(line.find_first_not_of(' ')));
  return lines;
}

}  // namespace deformation_enrichment
