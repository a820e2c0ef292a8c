#pragma once
// Helpers shared by the tests: temporary folders, the shared/ data folder, running the CLI, files
// written and read back, errors caught, BRDFBAKE_GNUPLOT set for a while.
#include <gtest/gtest.h>
#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <random>
#include <sstream>
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

/// The whole file as bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// Writes `bytes` to `path` as they are.
inline void put(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// The JSON document in `path`.
inline nlohmann::json readJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// How many of `folder`'s entries are AtomicOutput temporaries (".tmp-" in the name).
inline int hiddenTemporaries(const std::filesystem::path& folder) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().filename().string().find(".tmp-") != std::string::npos) ++count;
  }
  return count;
}

/// A CSV file (comma-separated, first line the header) as rows of column name -> text; a trailing
/// comma is an empty last cell. Every row must have the header's number of cells.
inline std::vector<std::map<std::string, std::string>> readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    if (header.empty()) {
      header = cells;
      continue;
    }
    EXPECT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

/// The message of the Error `f` throws ("" and a failure when it throws none).
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

/// The message of the Error `f` throws, which must be of kind `expected` ("(no error)" when it
/// throws none, which the caller's check of the message then reports).
template <class F>
std::string errorOf(F&& f, Error::Kind expected) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), expected) << e.what();
    return e.what();
  }
  return "(no error)";
}

/// A context of two worker threads (the machines the suite runs on have two cores).
inline const Context& twoThreads() {
  static const Context context({.threads = 2});
  return context;
}

/// The environment variable `name` set to `value` (std::nullopt: unset) while it lives; restored after.
class EnvironmentVariable {
 public:
  EnvironmentVariable(std::string name, const std::optional<std::string>& value) : name_(std::move(name)) {
    if (const char* old = std::getenv(name_.c_str())) old_ = old;
    if (value)
      ::setenv(name_.c_str(), value->c_str(), 1);
    else
      ::unsetenv(name_.c_str());
  }
  ~EnvironmentVariable() {
    if (old_)
      ::setenv(name_.c_str(), old_->c_str(), 1);
    else
      ::unsetenv(name_.c_str());
  }
  EnvironmentVariable(const EnvironmentVariable&) = delete;
  EnvironmentVariable& operator=(const EnvironmentVariable&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

/// BRDFBAKE_GNUPLOT set to `value` (std::nullopt: unset) while it lives; restored after.
class GnuplotVariable : public EnvironmentVariable {
 public:
  explicit GnuplotVariable(const std::optional<std::string>& value) : EnvironmentVariable("BRDFBAKE_GNUPLOT", value) {}
};

}  // namespace brdfbake::test
