#pragma once
// Terminal helpers for the CLI: progress bars on a TTY, vector parsing for flags.
#include <brdfbake/core/math.hpp>

#include <functional>
#include <string>

namespace brdfbake::cli {

/// A progress bar on stderr, drawn only when stderr is a terminal and `enabled`.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  /// Callback suitable for BakeOptions::progress (may be empty when disabled).
  std::function<void(double)> callback();

 private:
  void draw(double fraction);
  std::string label_;
  bool active_;
  int lastPercent_ = -1;
};

/// Parses "X,Y,Z" (three finite numbers); throws Error(InvalidArgument) naming `flag`.
Vec3 parseVector(const std::string& text, const std::string& flag);

/// True if stderr is a terminal.
bool stderrIsTerminal();

}  // namespace brdfbake::cli
