#pragma once
/// @file
/// What every job of the run layer takes and returns. A job is one library call doing what one
/// command of the `brdfbake` tool does (run a spec, chart it, prefilter an environment, fit a
/// table, ...): the tool parses its flags into the job's Options, calls the job, and prints the
/// result's briefReport() or, with --json, its toJson(). A renderer or a script makes the same call.
///
/// Every job:
///   - takes an Options struct deriving from JobOptions, whose validate() it calls before any work;
///   - checks every file it reads and writes (FilePlan) before any work, and writes outputs atomically;
///   - reports progress through JobOptions::progress (a sink may throw to cancel);
///   - returns a result with `files` (every file written), `notes`, `briefReport()` (the text the
///     tool prints) and `toJson()` (what `--json` prints);
///   - throws brdfbake::Error, never prints, never exits.

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>

#include <nlohmann/json.hpp>

#include <concepts>
#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake {

/// The settings every job shares.
struct JobOptions {
  /// Worker threads, 0 = every core; at most kMaxThreads.
  int threads = 0;
  /// Allow maps over 8192^2 texels (1 GiB of float RGBA); the memory budget still applies.
  bool allowLarge = false;
  /// Where progress goes (empty: nowhere). See ProgressSink.
  ProgressSink progress;

  /// The most worker threads a job accepts.
  static constexpr int kMaxThreads = 1024;

  /// Throws Error(InvalidArgument) naming the value unless threads is in [0, kMaxThreads].
  void validate() const;
};

/// What every job's result offers (see @file).
template <class R>
concept JobResult = requires(const R& result) {
  { result.briefReport() } -> std::convertible_to<std::string>;
  { result.toJson() } -> std::convertible_to<nlohmann::json>;
  { result.files } -> std::convertible_to<std::vector<std::filesystem::path>>;
  { result.notes } -> std::convertible_to<std::vector<std::string>>;
};

/// `paths` as a JSON array of strings.
nlohmann::json pathsToJson(const std::vector<std::filesystem::path>& paths);

}  // namespace brdfbake
