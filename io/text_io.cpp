#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/text_io.hpp>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <ctime>
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

}  // namespace

void writeStdout(std::string_view text) {
  const HeldSigpipe held;
  while (!text.empty()) {
    const ssize_t written = ::write(STDOUT_FILENO, text.data(), text.size());
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      const int error = written < 0 ? errno : ENOSPC;
      throw Error(Error::Kind::Io, "stdout: write failed (" + errnoText(error) + ")");
    }
    text.remove_prefix(static_cast<std::size_t>(written));
  }
}

}  // namespace brdfbake
