#pragma once
// Terminal helpers for the CLI: progress bars on a TTY, vector parsing for flags.
#include <brdfbake/core/math.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/output/baked_output.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>

namespace brdfbake::cli {

/// A progress bar on stderr, drawn only when stderr is a terminal and `enabled`.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  /// Callback suitable for BakeOptions::progress (may be empty when disabled).
  std::function<void(double)> callback();
  /// Clears the bar's line and stops drawing: call before printing results under it.
  void done();

 private:
  void draw(double fraction);
  std::string label_;
  bool active_;
  int lastPercent_ = -1;
};

/// The flags commands share, with one meaning on every command:
///   --json     print a machine-readable run report on stdout instead of text (`holds` says what)
///   --quiet    no progress bars, notes or "wrote" lines: only errors, and the values a query
///              command (sample, info, eval) exists to print
///   --threads  worker threads, 0 = all cores
void addJsonFlag(CLI::App* command, bool& json, const std::string& holds);
void addQuietFlag(CLI::App* command, bool& quiet);
void addThreadsOption(CLI::App* command, int& threads);
/// --max-error for prefiltered environments, in [1e-6, 0.5] as the spec's "max_error" of an
/// "environment" (chart and prefilter alike).
CLI::Option* addEnvironmentMaxErrorOption(CLI::App* command, double& maxError, const std::string& meaning);

/// Any output of bake or prefilter (BakedOutput::open), or with `from` (the --from flag) a plain
/// image of that parameterization, at mip level `mipLevel` (--mip-level). A plain image without
/// --from is an error that names the flag.
BakedOutput openOutput(const std::string& path, const std::string& from, int mipLevel = 0);

/// --cos-view C and --mip-level L, with one meaning on every command that reads outputs.
void addCosViewOption(CLI::App* command, std::optional<double>& cosView);
void addMipLevelOption(CLI::App* command, int& mipLevel);
/// Checks --cos-view against what `output` uses: required by stacks (and by Fresnel tables
/// when `fresnelNeedsIt`), refused by kinds that do not use it. Throws Error(InvalidArgument).
void checkCosView(const BakedOutput& output, const std::optional<double>& cosView, bool fresnelNeedsIt = true);

/// Parses "X,Y,Z" (three finite numbers); throws Error(InvalidArgument) naming `flag`.
Vec3 parseVector(const std::string& text, const std::string& flag);

/// True if stderr is a terminal.
bool stderrIsTerminal();

}  // namespace brdfbake::cli
