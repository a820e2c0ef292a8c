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

std::function<void(double)> ProgressBar::callback() {
  if (!active_) return {};
  return [this](double fraction) { draw(fraction); };
}

void ProgressBar::draw(double fraction) {
  const int percent = static_cast<int>(fraction * 100.0);
  if (percent == lastPercent_) return;
  lastPercent_ = percent;
  constexpr int width = 30;
  const int filled = percent * width / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "##############################",
               width - filled, "", percent);
  std::fflush(stderr);
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
