#include "terminal.hpp"

#include <brdfbake/core/error.hpp>

#include <unistd.h>

#include <cstdio>
#include <sstream>

namespace brdfbake::cli {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), active_(enabled && stderrIsTerminal()) {}

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
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "##############################", width - filled,
               "", percent);
  std::fflush(stderr);
}

void addJsonFlag(CLI::App* command, bool& json, const std::string& holds) {
  command->add_flag("--json", json, "Print a machine-readable report on stdout instead of text: " + holds);
}

void addQuietFlag(CLI::App* command, bool& quiet) {
  command->add_flag("--quiet", quiet, "No progress, notes or 'wrote' lines: only errors (and a query's values)");
}

void addThreadsOption(CLI::App* command, int& threads) {
  command->add_option("--threads", threads, "Worker threads (0 = all cores)")
      ->default_val(0)
      ->check(CLI::NonNegativeNumber);
}

CLI::Option* addEnvironmentMaxErrorOption(CLI::App* command, double& maxError, const std::string& meaning) {
  return command->add_option("--max-error", maxError, meaning + " (relative RMS, 0.01 = 1 %; in [1e-6, 0.5])")
      ->check(CLI::Range(1e-6, 0.5));
}

BakedOutput openOutput(const std::string& path, const std::string& from, int mipLevel) {
  OpenOutputOptions options;
  if (!from.empty()) options.from = parseParameterizationKind(from);
  options.fromName = "--from";
  options.mipLevel = mipLevel;
  return BakedOutput::open(path, options);
}

void addCosViewOption(CLI::App* command, std::optional<double>& cosView) {
  command
      ->add_option(
          "--cos-view", cosView,
          "n.v in [0, 1], the cosine between the surface normal and the direction towards the viewer: where an "
          "elevation stack is interpolated, and where a Fresnel table is read")
      ->check(CLI::Range(0.0, 1.0));
}

void addMipLevelOption(CLI::App* command, int& mipLevel) {
  command
      ->add_option("--mip-level", mipLevel,
                   "Read mip level L (0 = the map itself) of a map, cube faces or stack: from a tiled MIP-mapped file, "
                   "else from STEM_mipL.EXT")
      ->check(CLI::Range(0, 30));
}

void checkCosView(const BakedOutput& output, const std::optional<double>& cosView, bool fresnelNeedsIt) {
  const bool needs =
      output.kind() == OutputKind::ElevationStack || (fresnelNeedsIt && output.kind() == OutputKind::FresnelTable);
  const bool uses = needs || output.kind() == OutputKind::FresnelTable;
  if (needs && !cosView) {
    throw Error(Error::Kind::InvalidArgument,
                "--cos-view: a" +
                    std::string(output.kind() == OutputKind::ElevationStack ? "n elevation stack is interpolated at n.v"
                                                                            : " Fresnel table is read at n.v") +
                    "; give --cos-view C (C = n.v in [0, 1])");
  }
  if (cosView && !uses) {
    throw Error(Error::Kind::InvalidArgument,
                "--cos-view: a " + std::string(toString(output.kind())) +
                    " is looked up by direction alone (n.v applies to elevation stacks and Fresnel "
                    "profiles)");
  }
  if (cosView && !needs) {
    throw Error(Error::Kind::InvalidArgument,
                "--cos-view: here a Fresnel table takes n.v from each direction (the view +z)");
  }
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
      if (used != part.size() && part.find_first_not_of(" \t", used) != std::string::npos)
        throw std::invalid_argument(part);
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
