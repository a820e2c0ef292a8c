#pragma once
/// @file
/// Line-oriented text in and out of the command line: files of one record per line (`eval --pairs`,
/// `sample --dirs`) read with bounds, reports and messages written with every write checked, and
/// progress shown as text.

#include <brdfbake/core/progress.hpp>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// Bounds of a line-oriented input file (docs/limits.md).
struct LineFileLimits {
  std::size_t maxBytes = std::size_t{64} << 20;  ///< the whole file: 64 MiB
  std::size_t maxLines = std::size_t{4} << 20;   ///< 4,194,304 lines
  std::size_t maxLineBytes = 4096;               ///< one line, without its end
};

/// The lines of a text file, without their "\n" or "\r\n"; a last line without an end is kept.
/// The file must be a regular file (requireInputFile: /dev/zero, FIFOs and sockets are refused,
/// never read), and is read with a bound. Throws Error(Io) naming the file when it cannot be read,
/// Error(InvalidInput) "<file>: more than N bytes (<what>)", "<file>:<line>: longer than 4096 bytes"
/// or "<file>: more than N lines" beyond `limits`. File names go through printable().
std::vector<std::string> readTextLines(const std::filesystem::path& path, const std::string& what,
                                       const LineFileLimits& limits = {});

/// Writes `text` to standard output (file descriptor 1) with write(2), unbuffered, checking every
/// write: throws Error(Io) "stdout: write failed (No space left on device)" on a full disk
/// (/dev/full), "stdout: write failed (Broken pipe)" when the reader has gone (SIGPIPE is held back
/// while it writes, so the process is not killed), "stdout: write failed (Bad file descriptor)"
/// when stdout is closed. Callers that also use std::cout flush it first.
void writeStdout(std::string_view text);

/// Writes a message for a person to standard error (file descriptor 2) as writeStdout writes, with
/// the control characters of untrusted text escaped (printableMessage): "stderr: write failed (...)".
void writeStderr(std::string_view message);

/// Progress as text on a file descriptor (standard error by default), as the command line shows it:
/// a bar "TASK [#####     ]  40%" redrawn in place when the descriptor is a terminal, else plain lines
/// "brdfbake: TASK: 25 %" (a task's start, each quarter reached a second or more after the last
/// line, "brdfbake: TASK: done" at its end, the fraction 1; the time is the job report's, printed once).
/// Nothing when disabled.
class TextProgress {
 public:
  explicit TextProgress(bool enabled = true, int fd = 2);
  ~TextProgress();
  TextProgress(const TextProgress&) = delete;
  TextProgress& operator=(const TextProgress&) = delete;

  /// A sink reporting here (empty when disabled); it must not outlive this object.
  ProgressSink sink();
  /// Clears a bar before results are printed under it.
  void finish();

 private:
  void report(const std::string& task, double fraction);
  void write(const std::string& text);
  bool enabled_, terminal_;
  int fd_;
  std::mutex mutex_;
  std::string task_;
  int lastQuarter_ = -1, lastPercent_ = -1;
  std::chrono::steady_clock::time_point lastLine_;
};

}  // namespace brdfbake
