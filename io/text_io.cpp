#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/text_io.hpp>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <ctime>
#include <iomanip>
#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;

std::vector<std::string> readTextLines(const fs::path& path, const std::string& what, const LineFileLimits& limits) {
  const std::string name = printable(path.string());
  std::string text;
  try {
    text = readTextFile(path, what, limits.maxBytes);
  } catch (const Error& e) {
    if (e.kind() != Error::Kind::Resource) throw;
    throw Error(Error::Kind::InvalidInput,
                name + ": more than " + std::to_string(limits.maxBytes) + " bytes (" + what + "; docs/limits.md)");
  }
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::size_t length = end - begin;
    if (length > 0 && text[end - 1] == '\r') --length;
    if (lines.size() == limits.maxLines) {
      throw Error(Error::Kind::InvalidInput,
                  name + ": more than " + std::to_string(limits.maxLines) + " lines (" + what + "; docs/limits.md)");
    }
    if (length > limits.maxLineBytes) {
      throw Error::atFile(
          Error::Kind::InvalidInput, path.string(), static_cast<int>(lines.size() + 1),
          "longer than " + std::to_string(limits.maxLineBytes) + " bytes (" + what + "; docs/limits.md)");
    }
    lines.emplace_back(text, begin, length);
    begin = end + 1;
  }
  return lines;
}

namespace {

// SIGPIPE blocked in this thread while it lives; a SIGPIPE raised meanwhile (by a write to a pipe
// whose reader has gone) is consumed before it is unblocked, so the write fails with EPIPE instead
// of killing the process.
class HeldSigpipe {
 public:
  HeldSigpipe() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    sigset_t pending;
    sigemptyset(&pending);
    wasPending_ = sigpending(&pending) == 0 && sigismember(&pending, SIGPIPE) == 1;
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
  }
  ~HeldSigpipe() {
    if (!wasPending_) {
      const timespec none{0, 0};
      while (sigtimedwait(&pipe_, nullptr, &none) == -1 && errno == EINTR) {
      }
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  HeldSigpipe(const HeldSigpipe&) = delete;
  HeldSigpipe& operator=(const HeldSigpipe&) = delete;

 private:
  sigset_t pipe_, old_;
  bool wasPending_ = false;
};

// Writes all of `text` to `fd`; the errno of a failed write, else 0.
int writeAll(int fd, std::string_view text) {
  const HeldSigpipe held;
  while (!text.empty()) {
    const ssize_t written = ::write(fd, text.data(), text.size());
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return written < 0 ? errno : ENOSPC;
    text.remove_prefix(static_cast<std::size_t>(written));
  }
  return 0;
}

}  // namespace

void writeStdout(std::string_view text) {
  if (const int error = writeAll(STDOUT_FILENO, text))
    throw Error(Error::Kind::Io, "stdout: write failed (" + errnoText(error) + ")");
}

void writeStderr(std::string_view message) {
  if (const int error = writeAll(STDERR_FILENO, printableMessage(message)))
    throw Error(Error::Kind::Io, "stderr: write failed (" + errnoText(error) + ")");
}

TextProgress::TextProgress(bool enabled, int fd) : enabled_(enabled), terminal_(::isatty(fd) == 1), fd_(fd) {}

TextProgress::~TextProgress() { finish(); }

ProgressSink TextProgress::sink() {
  if (!enabled_) return {};
  return [this](const std::string& task, double fraction) { report(task, fraction); };
}

void TextProgress::finish() {
  std::lock_guard lock(mutex_);
  if (terminal_ && lastPercent_ >= 0) write("\r\033[K");
  lastPercent_ = -1;
}

// Progress is shown as well as it can be: a failed write does not fail the job.
void TextProgress::write(const std::string& text) { writeAll(fd_, text); }

void TextProgress::report(const std::string& task, double fraction) {
  std::lock_guard lock(mutex_);
  const bool newTask = task != task_;
  if (newTask) task_ = task, lastQuarter_ = -1, lastPercent_ = -1, lastLine_ = std::chrono::steady_clock::now();
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
  if (terminal_) {
    if (percent == lastPercent_) return;
    lastPercent_ = percent;
    constexpr int width = 30;
    const int filled = percent * width / 100;
    std::ostringstream bar;
    bar << "\r\033[K" << printable(task, 60) << " [" << std::string(filled, '#') << std::string(width - filled, ' ')
        << "] " << std::setw(3) << percent << "%";
    write(bar.str());
    return;
  }
  // Plain lines: the start, each quarter reached a second or more after the last line, the end.
  const int quarter = percent / 25;
  const auto t = std::chrono::steady_clock::now();
  const bool end = fraction >= 1.0 && lastQuarter_ < 4;
  if (!newTask && !end && (quarter <= lastQuarter_ || secondsSince(lastLine_) < 1.0)) return;
  if (!newTask && !end && quarter == 4) return;  // 100 % is printed as the end
  lastQuarter_ = end ? 4 : std::max(quarter, lastQuarter_);
  lastLine_ = t;
  std::ostringstream line;
  line << "brdfbake: " << task << ": ";
  if (end) {
    line << "done\n";  // the job's own report gives its time, once (stdout, --json)
  } else {
    line << percent << " %\n";
  }
  write(printableMessage(line.str()));
}

}  // namespace brdfbake
