#include "terminal.hpp"

#include <brdfbake/core/error.hpp>

#include <unistd.h>

#include <cstdio>
#include <sstream>

namespace brdfbake::cli {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, bool enabled) : label_(std::move(label)), active_(enabled && stderrIsTerminal()) {}

ProgressBar::~ProgressBar() {
  if (active_ && lastPercent_ >= 0) std::fprintf(stderr, "\r\033[K");
}

void ProgressBar::done() {
  if (active_ && lastPercent_ >= 0) std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  active_ = false;
}

std::function<void(double)> ProgressBar::callback() {
  if (!active_) return {};
  return [this](double fraction) { draw(fraction); };
}

void ProgressBar::draw(double fraction) {
  if (!active_) return;
  const int percent = static_cast<int>(fraction * 100.0);
  if (percent == lastPercent_) return;
  lastPercent_ = percent;
  constexpr int width = 30;
  const int filled = percent * width / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "##############################",
               width - filled, "", percent);
  std::fflush(stderr);
}

void addJsonFlag(CLI::App* command, bool& json, const std::string& holds) {
  command->add_flag("--json", json, "Print a machine-readable report on stdout instead of text: " + holds);
}

void addQuietFlag(CLI::App* command, bool& quiet) {
  command->add_flag("--quiet", quiet, "No progress, notes or 'wrote' lines: only errors (and a query's values)");
}

void addThreadsOption(CLI::App* command, int& threads) {
  command->add_option("--threads", threads, "Worker threads (0 = all cores)")->default_val(0)->check(CLI::NonNegativeNumber);
}

CLI::Option* addEnvironmentMaxErrorOption(CLI::App* command, double& maxError, const std::string& meaning) {
  return command->add_option("--max-error", maxError, meaning + " (relative RMS, 0.01 = 1 %; in [1e-6, 0.5])")
      ->check(CLI::Range(1e-6, 0.5));
}

MapFile openMapOrImage(const std::string& path, const std::string& from) {
  Image image = readImage(path);
  if (!from.empty()) return adoptImage(std::move(image), parseParameterizationKind(from), path);
  if (!hasMapMetadata(image)) {
    throw Error(Error::Kind::InvalidInput, path + ": not a brdfbake map (no brdfbake metadata); for a plain environment "
                                                  "image, say which parameterization it uses with --from "
                                                  "sphere|paraboloid|cube|latlong");
  }
  return mapFromImage(std::move(image), path);
}

Vec3 parseVector(const std::string& text, const std::string& flag) {
  std::stringstream in(text);
  Vec3 v;
  std::string part;
  int count = 0;
  while (std::getline(in, part, ',')) {
    if (count == 3) break;
    try {
      std::size_t used = 0;
      v[count] = std::stod(part, &used);
      if (used != part.size() && part.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw Error(Error::Kind::InvalidArgument, flag + ": expected three numbers X,Y,Z, got '" + text + "'");
    }
    ++count;
  }
  if (count != 3 || std::getline(in, part, ',') || !v.allFinite()) {
    throw Error(Error::Kind::InvalidArgument, flag + ": expected three finite numbers X,Y,Z, got '" + text + "'");
  }
  return v;
}

}  // namespace brdfbake::cli
