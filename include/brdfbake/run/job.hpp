#pragma once
/// @file
/// What every job of the run layer takes and returns. A job is one library call doing what one
/// command of the `brdfbake` tool does (run a spec, chart it, prefilter an environment, fit a
/// table, ...): the tool parses its flags into the job's request, calls the job, and prints the
/// result's briefReport() or, with --json, its toJson(). A renderer or a script makes the same call.
///
/// Every job:
///   - takes its typed request and a Context (core/context.hpp: threads, limits, progress and
///     cancellation, passed the way Filament passes its JobSystem&); it validates the request first,
///     and its errors name a field in the request's own terms (Error::invalidField: "max_error"),
///     which each front maps once to its own name (a flag, a spec key, a keyword);
///   - computes in memory; the jobs that also write (run*, runSpec) check every file they read and
///     write (FilePlan) before any work and write outputs atomically;
///   - reports progress through the Context, checks it for cancellation often, and then throws
///     Cancelled, leaving no output of the unfinished step behind;
///   - returns a result with `briefReport()` (the text the tool prints) and `toJson()` (what
///     `--json` prints), and, when it wrote, `files` (every file written) and `notes`;
///   - throws brdfbake::Error, never prints, never exits.

#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>

#include <nlohmann/json.hpp>

#include <concepts>
#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake {

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
