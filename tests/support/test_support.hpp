#pragma once
// Helpers shared by the tests: temporary folders, the shared/ data folder, running the CLI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace brdfbake::test {

/// A fresh empty folder under the system temp dir, removed at destruction.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("brdfbake-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// ../shared/<relative>, or an empty path if the shared folder is absent.
inline std::filesystem::path sharedPath(const std::string& relative) {
  const std::filesystem::path p = std::filesystem::path(BRDFBAKE_SHARED_DIR) / relative;
  return std::filesystem::exists(p) ? p : std::filesystem::path();
}

/// Skips the current test with a clear message when ../shared/<relative> is absent.
#define BRDFBAKE_REQUIRE_SHARED(var, relative)                                                                  \
  const std::filesystem::path var = ::brdfbake::test::sharedPath(relative);                                     \
  if (var.empty())                                                                                              \
  GTEST_SKIP() << "shared data '" << (relative) << "' not found beside the repository (" << BRDFBAKE_SHARED_DIR \
               << "); skipping"

/// Result of running a command.
struct CommandResult {
  int exitCode = -1;
  std::string out;     // stdout
  std::string err;     // stderr
  std::string output;  // stdout, then stderr
};

/// Runs a shell command line, capturing stdout and stderr (stderr through a scratch file).
inline CommandResult run(const std::string& commandLine) {
  CommandResult result;
  std::random_device rd;
  const std::filesystem::path errors =
      std::filesystem::temp_directory_path() / ("brdfbake-test-stderr-" + std::to_string(rd()) + std::to_string(rd()));
  FILE* pipe = popen(("(" + commandLine + ") 2>'" + errors.string() + "'").c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) result.out.append(buffer, n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (FILE* err = std::fopen(errors.c_str(), "rb")) {
    while (std::size_t n = std::fread(buffer, 1, sizeof buffer, err)) result.err.append(buffer, n);
    std::fclose(err);
  }
  std::error_code ec;
  std::filesystem::remove(errors, ec);
  result.output = result.out + result.err;
  return result;
}

/// A path in single quotes, for runCli's shell command line.
inline std::string q(const std::filesystem::path& p) { return std::string("'").append(p.string()).append("'"); }

/// Runs the brdfbake CLI with arguments (already shell-quoted as needed).
inline CommandResult runCli(const std::string& arguments) { return run(std::string(BRDFBAKE_CLI) + " " + arguments); }

inline std::string sourcePath(const std::string& relative) { return std::string(BRDFBAKE_SOURCE_DIR) + "/" + relative; }

/// Every file and folder under `folder`, relative to it, sorted (empty if it does not exist).
inline std::vector<std::string> filesIn(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  if (!std::filesystem::exists(folder)) return names;
  for (const auto& e : std::filesystem::recursive_directory_iterator(folder)) {
    names.push_back(std::filesystem::relative(e.path(), folder).string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace brdfbake::test
