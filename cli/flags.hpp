#pragma once
// What every command of the tool shares: the flags with one meaning everywhere, progress on stderr,
// and printing a job's result. The commands only parse flags and call one library job each.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/run/job.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake::cli {

/// The flags every command has, with one meaning on every command:
///   --json      print the job's result as JSON on stdout instead of text
///   --quiet     no progress, notes or "wrote" lines: only errors (and a query's values)
///   --threads   worker threads, 0 = every core (commands that compute)
struct CommonFlags {
  bool json = false, quiet = false;
  int threads = 0;
  bool allowLarge = false;
};
/// --json and --quiet; `holds` says what --json prints.
void addOutputFlags(CLI::App* command, CommonFlags& flags, const std::string& holds);
/// --threads, and --allow-large when the command makes maps.
void addComputeFlags(CLI::App* command, CommonFlags& flags, bool makesMaps);

/// Progress on stderr: a bar redrawn in place on a terminal, else plain lines (a task's start,
/// every quarter after a second, its end), nothing with --quiet.
class ProgressPrinter {
 public:
  explicit ProgressPrinter(const CommonFlags& flags);
  ~ProgressPrinter();
  ProgressSink sink();
  /// Clears a bar before results are printed under it.
  void finish();

 private:
  void report(const std::string& task, double fraction);
  bool enabled_, terminal_;
  std::mutex mutex_;
  std::string task_;
  int lastQuarter_ = -1, lastPercent_ = -1;
  double lastLine_ = 0.0, started_ = 0.0;
};

/// The Context the flags ask for (threads, large maps), reporting to `progress`.
Context jobContext(const CommonFlags& flags, ProgressPrinter& progress);

/// job(request, context) with the context the flags ask for and progress on stderr, cleared before
/// the result is returned (to be printed).
template <class Request, class Job>
auto withProgress(const CommonFlags& flags, const Request& request, Job job) {
  ProgressPrinter progress(flags);
  auto result = job(request, jobContext(flags, progress));
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

/// Writes a message to stderr with control characters of untrusted text escaped.
void writeStderr(const std::string& text);

/// "X,Y,Z": three finite numbers; throws Error(InvalidArgument) naming `flag`.
Vec3 parseVector(const std::string& text, const std::string& flag);

/// A comma-separated list, each item turned into a value by `parse` (which throws on a bad item);
/// throws Error(InvalidArgument) naming `flag` and the item.
template <class T, class Parse>
std::vector<T> parseList(const std::string& text, const std::string& flag, Parse parse) {
  std::vector<T> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, end - start);
    try {
      out.push_back(parse(item));
    } catch (const std::exception&) {
      throw Error(Error::Kind::InvalidArgument, flag + ": cannot read '" + item.substr(0, 40) + "' in the list");
    }
    start = end + 1;
  }
  if (out.empty()) throw Error(Error::Kind::InvalidArgument, flag + ": empty list");
  return out;
}
/// parse(text) (a library parse* function), its error prefixed with the flag's name.
template <class Parse>
auto parseFlag(const std::string& flag, const std::string& text, Parse parse) {
  try {
    return parse(text);
  } catch (const Error& e) {
    throw Error(e.kind(), flag + ": " + e.what());
  }
}

/// A whole number (all of `text`); throws std::invalid_argument otherwise.
int parseWholeNumber(const std::string& text);
/// A finite number (all of `text`); throws std::invalid_argument otherwise.
double parseFiniteNumber(const std::string& text);

/// --cos-view C and --mip-level L, with one meaning on every command that reads outputs.
void addCosViewOption(CLI::App* command, std::optional<double>& cosView);
void addMipLevelOption(CLI::App* command, int& mipLevel);
/// --from KIND: the parameterization of a plain (metadata-free) image.
void addFromOption(CLI::App* command, std::string& from);
/// --from KIND for an environment image (its metadata, else its shape, when not given).
void addEnvironmentFromOption(CLI::App* command, std::optional<std::string>& from);
/// --to KIND: the output parameterization (required).
void addToOption(CLI::App* command, std::string& to);
/// --resolution N of a map: texels per side, hemisphere or face, or rows; 1 to 65536, default 256.
void addMapResolutionOption(CLI::App* command, int& resolution);
/// --max-error E in [1e-6, 0.5], default 0.01; `bound` says what it bounds.
void addMaxErrorOption(CLI::App* command, double& maxError, const std::string& bound);
/// --samples-per-texel N in [1, 4096], default 16 (and the hidden old spelling --samples when
/// `oldSpelling`).
void addSamplesPerTexelOption(CLI::App* command, int& samples, const std::string& help, bool oldSpelling);

/// The containers every output file may be, for -o's help: chosen by the extension.
inline constexpr const char* kOutputContainers = ".exr .hdr .tif .png .ktx2 .ktx .dds";

/// -o FILE, repeatable: the first file and the rest (one computation, written in each file's format).
struct OutputFiles {
  std::vector<std::string> files;
  std::string first() const { return files.empty() ? std::string() : files.front(); }
  std::vector<std::filesystem::path> rest() const { return {files.begin() + (files.empty() ? 0 : 1), files.end()}; }
  std::vector<std::filesystem::path> paths() const { return {files.begin(), files.end()}; }
};
/// -o,--output FILE (required; repeat it to write the one map in several formats), `what` the help's noun.
void addOutputFileOption(CLI::App* command, OutputFiles& outputs, const std::string& what);
/// --texel-format NAME: how .ktx2, .ktx and .dds outputs store texels; the help lists the names.
void addTexelFormatOption(CLI::App* command, std::optional<std::string>& texelFormat);
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
