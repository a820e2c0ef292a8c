#include "flags.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace brdfbake::cli {

namespace {

double now() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

void writeAll(int fd, const std::string& text, const char* name) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t written = ::write(fd, text.data() + done, text.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) throw Error(Error::Kind::Io, std::string(name) + ": write failed (" + std::strerror(errno) + ")");
    done += static_cast<std::size_t>(written);
  }
}

}  // namespace

void addOutputFlags(CLI::App* command, CommonFlags& flags, const std::string& holds) {
  command->add_flag("--json", flags.json, "Print a machine-readable report on stdout instead of text: " + holds);
  command->add_flag("--quiet", flags.quiet, "No progress, notes or 'wrote' lines: only errors (and a query's values)");
}

void addComputeFlags(CLI::App* command, CommonFlags& flags, bool makesMaps) {
  command->add_option("--threads", flags.threads, "Worker threads (0 = every core)")
      ->default_val(0)
      ->check(CLI::Range(0, kMaxThreads));
  if (makesMaps) {
    command->add_flag("--allow-large", flags.allowLarge, "Allow maps over 8192^2 texels (1 GiB of float RGBA)");
  }
}

ProgressPrinter::ProgressPrinter(const CommonFlags& flags)
    : enabled_(!flags.quiet), terminal_(::isatty(STDERR_FILENO) == 1) {}

ProgressPrinter::~ProgressPrinter() { finish(); }

ProgressSink ProgressPrinter::sink() {
  if (!enabled_) return {};
  return [this](const std::string& task, double fraction) { report(task, fraction); };
}

void ProgressPrinter::finish() {
  std::lock_guard lock(mutex_);
  if (terminal_ && lastPercent_ >= 0) std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  lastPercent_ = -1;
}

void ProgressPrinter::report(const std::string& task, double fraction) {
  std::lock_guard lock(mutex_);
  const bool newTask = task != task_;
  if (newTask) task_ = task, lastQuarter_ = -1, lastPercent_ = -1, started_ = lastLine_ = now();
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
  if (terminal_) {
    if (percent == lastPercent_) return;
    lastPercent_ = percent;
    constexpr int width = 30;
    const int filled = percent * width / 100;
    std::fprintf(stderr, "\r\033[K%s [%.*s%*s] %3d%%", printable(task, 60).c_str(), filled,
                 "##############################", width - filled, "", percent);
    std::fflush(stderr);
    return;
  }
  // Plain lines: the start, each quarter reached a second or more after the last line, the end.
  const int quarter = percent / 25;
  const double t = now();
  const bool end = fraction >= 1.0 && lastQuarter_ < 4;
  if (!newTask && !end && (quarter <= lastQuarter_ || t - lastLine_ < 1.0)) return;
  if (!newTask && !end && quarter == 4) return;  // 100 % is printed as the end
  lastQuarter_ = end ? 4 : std::max(quarter, lastQuarter_);
  lastLine_ = t;
  std::ostringstream line;
  line << "brdfbake: " << task << ": ";
  if (end) {
    line.precision(3);
    line << "done (" << t - started_ << " s)\n";
  } else {
    line << percent << " %\n";
  }
  std::fputs(printableMessage(line.str()).c_str(), stderr);
  std::fflush(stderr);
}

Context jobContext(const CommonFlags& flags, ProgressPrinter& progress) {
  return Context({.threads = flags.threads, .allowLarge = flags.allowLarge, .progress = progress.sink()});
}

void printJsonOrText(const nlohmann::json& json, const std::string& text, const CommonFlags& flags, int indent) {
  if (!json.is_null()) {
    writeStdout(json.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  } else if (!flags.quiet) {
    writeStdout(printableMessage(text));
  }
}

void writeStderr(const std::string& text) { writeAll(STDERR_FILENO, printableMessage(text), "stderr"); }

Vec3 parseVector(const std::string& text, const std::string& flag) {
  std::stringstream in(text);
  Vec3 v;
  std::string part;
  int count = 0;
  const auto bad = [&] {
    return Error(Error::Kind::InvalidArgument,
                 flag + ": expected three finite numbers X,Y,Z, got '" + shortenForMessage(text, 80) + "'");
  };
  while (std::getline(in, part, ',')) {
    if (count == 3) throw bad();
    std::size_t used = 0;
    try {
      v[count] = std::stod(part, &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (part.find_first_not_of(" \t", used) != std::string::npos) throw bad();
    ++count;
  }
  if (count != 3 || !v.allFinite()) throw bad();
  return v;
}

int parseWholeNumber(const std::string& text) {
  std::size_t used = 0;
  const int value = std::stoi(text, &used);
  if (used != text.size()) throw std::invalid_argument(text);
  return value;
}

double parseFiniteNumber(const std::string& text) {
  std::size_t used = 0;
  const double value = std::stod(text, &used);
  if (used != text.size() || !std::isfinite(value)) throw std::invalid_argument(text);
  return value;
}

void addCosViewOption(CLI::App* command, std::optional<double>& cosView) {
  command
      ->add_option("--cos-view", cosView,
                   "n.v in [0, 1], the cosine between the surface normal and the direction towards the viewer: where "
                   "an elevation stack is interpolated, and where a Fresnel table is read")
      ->check(CLI::Range(0.0, 1.0));
}

void addMipLevelOption(CLI::App* command, int& mipLevel) {
  command
      ->add_option("--mip-level", mipLevel,
                   "Read mip level L (0 = the map itself) of a map, cube faces or stack: from a tiled MIP-mapped "
                   "file, else from STEM_mipL.EXT")
      ->check(CLI::Range(0, 30));
}

void addFromOption(CLI::App* command, std::string& from) {
  command->add_option("--from", from, "Parameterization of a plain image (no brdfbake metadata)")
      ->check(CLI::IsMember({"sphere", "paraboloid", "cube", "latlong"}));
}

void addOutputFileOption(CLI::App* command, OutputFiles& outputs, const std::string& what) {
  command
      ->add_option(
          "-o,--output", outputs.files,
          what + " (" + kOutputContainers + "); repeat -o to write the one map in several formats, computed once")
      ->required()
      ->allow_extra_args(false)  // one file per -o, so `-o OUT ENV` leaves ENV to the positional
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void addTexelFormatOption(CLI::App* command, std::optional<std::string>& texelFormat) {
  command->add_option("--texel-format", texelFormat,
                      ".ktx2 .ktx .dds texels: rgba16f (default) | rgba32f | rgb16f | rgb32f | rgb9e5 | rg11b10f");
}

void addEnvironmentFromOption(CLI::App* command, std::optional<std::string>& from) {
  command->add_option("--from", from, "Parameterization of a plain environment image (default: metadata, shape)");
}

void addToOption(CLI::App* command, std::string& to) {
  command->add_option("--to", to, "Output parameterization")
      ->required()
      ->check(CLI::IsMember({"sphere", "paraboloid", "cube", "latlong"}));
}

void addMapResolutionOption(CLI::App* command, int& resolution) {
  command->add_option("--resolution", resolution, "Texels per side (sphere), hemisphere, face, or rows (latlong)")
      ->default_val(256)
      ->check(CLI::Range(1, 65536));
}

void addMaxErrorOption(CLI::App* command, double& maxError, const std::string& bound) {
  command->add_option("--max-error", maxError, bound)->default_val(0.01)->check(CLI::Range(1e-6, 0.5));
}

void addSamplesPerTexelOption(CLI::App* command, int& samples, const std::string& help, bool oldSpelling) {
  command->add_option("--samples-per-texel", samples, help)->default_val(16)->check(CLI::Range(1, 4096));
  if (oldSpelling) command->add_option("--samples", samples, "(old spelling of --samples-per-texel)")->group("");
}

std::string flagFor(const std::string& field, const FieldFlags& renamed) {
  for (const auto& [name, flag] : renamed)
    if (name == field) return flag;
  std::string flag = "--" + field;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

Error namedByFlag(const Error& error, const FieldFlags& renamed) {
  if (!error.field().empty()) return Error(error.kind(), flagFor(error.field(), renamed) + ": " + error.problem());
  const std::string message = error.what();
  for (const auto& [field, flag] : renamed) {
    if (message.rfind(field + ": ", 0) == 0) return Error(error.kind(), flag + message.substr(field.size()));
  }
  return error;
}

}  // namespace brdfbake::cli
