#pragma once
// What every command of the tool shares: the flags with one meaning everywhere, read straight into
// the library's typed requests by the library's own parsers, progress on stderr, and printing a
// job's result. The commands only declare flags and call one library job each.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/run/job.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/sample_output.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake::cli {

/// The flags every command has, with one meaning on every command:
///   --json         print the job's result as JSON on stdout instead of text
///   --quiet        no progress, notes or "wrote" lines: only errors (and a query's values)
///   --threads      worker threads, 0 = every core (commands that compute)
///   --allow-large  maps over 8192^2 texels (commands that make maps)
struct CommonFlags {
  bool json = false, quiet = false, allowLarge = false;
  int threads = 0;
};
/// What a command computes, which decides the common flags it takes.
enum class Computes { Nothing, Values, Maps };
/// --json (`holds` says what it prints) and --quiet; --threads unless Nothing; --allow-large for Maps.
void addCommonFlags(CLI::App* command, CommonFlags& flags, Computes computes, const std::string& holds);

/// job(request, context) on the Context the flags ask for (threads, large maps) with progress on
/// stderr (TextProgress, none with --quiet), cleared before the result is returned (to be printed).
template <class Request, class Job>
auto withProgress(const CommonFlags& flags, const Request& request, Job job) {
  TextProgress progress(!flags.quiet);
  auto result =
      job(request, Context({.threads = flags.threads, .allowLarge = flags.allowLarge, .progress = progress.sink()}));
  progress.finish();
  return result;
}

/// Prints JSON (when not null; `indent` as nlohmann's dump) or else the text unless --quiet, checked.
void printJsonOrText(const nlohmann::json& json, const std::string& text, const CommonFlags& flags, int indent = 2);

/// Whether a command exists to print values (sample, eval, info: printed even with --quiet).
enum class Printing { Report, Query };

/// Prints a job's result: toJson() with --json, else briefReport() (a report not with --quiet).
/// Returns 0.
template <JobResult R>
int printResult(const R& result, const CommonFlags& flags, Printing printing = Printing::Report, int indent = 2) {
  CommonFlags shown = flags;
  if (printing == Printing::Query) shown.quiet = false;
  printJsonOrText(flags.json ? result.toJson() : nlohmann::json(), flags.json ? "" : result.briefReport(), shown,
                  indent);
  return 0;
}

// Parsers of flag values (with the library's parseFiniteNumber, parseWholeNumber and parse* of
// names): each takes the text and throws Error(InvalidArgument) saying what it expected; addParsed
// names the flag.

/// "X,Y,Z": three finite numbers.
Vec3 parseVec3(const std::string& text);
/// A comma-separated list, each item read by `parse`.
template <class Parse>
auto listOf(Parse parse) {
  return [parse](const std::string& text) {
    std::vector<std::decay_t<decltype(parse(text))>> out;
    for (std::size_t start = 0; start <= text.size();) {
      const std::size_t end = std::min(text.find(',', start), text.size());
      out.push_back(parse(text.substr(start, end - start)));
      start = end + 1;
    }
    return out;
  };
}

/// -x,--name TEXT read into `target` by `parse` (a parser above or a library parse* function:
/// parseParameterizationKind, parseTexelFormat, ...) as the command line is read; what it throws
/// becomes a usage error naming the flag: "--to: parameterization must be one of ...".
template <class T, class Parse>
CLI::Option* addParsed(CLI::App* command, const std::string& names, T& target, Parse parse, const std::string& help) {
  const std::string flag = names.substr(names.rfind(',') + 1);
  auto read = [&target, parse, flag](const std::string& text) {
    try {
      target = parse(text);
    } catch (const std::exception& e) {
      throw CLI::ValidationError(flag, e.what());
    }
  };
  return command->add_option_function<std::string>(names, read, help);
}

/// MAP (a positional), --from, --mip-level, and --cos-view when `cosView`: an output to read.
void addSourceOptions(CLI::App* command, OutputSource& source, bool cosView);
/// ENV (a positional: an environment image) and --from (its parameterization when plain).
void addEnvironmentOptions(CLI::App* command, std::filesystem::path& environment,
                           std::optional<ParameterizationKind>& from);
/// --to KIND: the output parameterization (required).
void addToOption(CLI::App* command, ParameterizationKind& to);
/// --resolution N of a map: texels per side, hemisphere or face, or rows; 1 to 65536, default 256.
void addMapResolutionOption(CLI::App* command, int& resolution);
/// --max-error E in [1e-6, 0.5], default 0.01; `bound` says what it bounds.
void addMaxErrorOption(CLI::App* command, double& maxError, const std::string& bound);
/// --samples-per-texel N in [1, 4096], default 16 (and the hidden old spelling --samples when
/// `oldSpelling`).
void addSamplesPerTexelOption(CLI::App* command, int& samples, const std::string& help, bool oldSpelling);
/// --texel-format NAME: how .ktx2, .ktx and .dds outputs store texels.
void addTexelFormatOption(CLI::App* command, std::optional<TexelFormat>& texelFormat);

/// The containers every output file may be, for -o's help: chosen by the extension.
inline constexpr const char* kOutputContainers = ".exr .hdr .tif .png .ktx2 .ktx .dds";

/// -o FILE (required; repeat it to write the one map in several formats, computed once),
/// --texel-format and --faces (a cube as six files), into `outputs`.
void addMapOutputOptions(CLI::App* command, MapOutputs& outputs);

/// How a command names the fields of its request that are not "--" + the field with '-' for '_'
/// (field, flag): {"parameterization", "--to"}, {"outputs", "-o"}.
using FieldFlags = std::vector<std::pair<std::string, std::string>>;
/// The flag of a request field: `renamed`'s, else "--max-error" for "max_error".
std::string flagFor(const std::string& field, const FieldFlags& renamed = {});
/// The error with the request field it names (Error::field, or a message starting "FIELD: " for a
/// field of `renamed`) written as its flag: "--max-error: must be in (0, 0.5], got 2".
Error namedByFlag(const Error& error, const FieldFlags& renamed);

/// f(), its errors naming request fields by their flags (namedByFlag).
template <class F>
auto namingFields(const FieldFlags& renamed, F&& f) {
  try {
    return f();
  } catch (const Error& error) {
    throw namedByFlag(error, renamed);
  }
}

}  // namespace brdfbake::cli
