#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

bool executableFile(const fs::path& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

std::optional<fs::path> onPath() {
  const char* path = std::getenv("PATH");
  std::stringstream folders(path ? path : "/usr/bin:/bin");
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) continue;
    const fs::path candidate = fs::path(folder) / "gnuplot";
    if (executableFile(candidate)) return candidate;
  }
  return std::nullopt;
}

// "exited with status 1", "was killed by signal 9 (Killed)": a wait status in words.
std::string describeWaitStatus(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    const char* name = ::strsignal(WTERMSIG(status));
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + (name ? std::string(" (") + name + ")" : "");
  }
  return "stopped (wait status " + std::to_string(status) + ")";
}

// gnuplot's messages: the first 64 KiB of its stderr, lines joined by " / ", made printable.
std::string readMessages(const fs::path& log) {
  std::string text;
  try {
    text = readTextFile(log, "gnuplot messages", 64 * 1024);
  } catch (const Error&) {
    return "(its messages could not be read)";
  }
  std::string joined;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (!joined.empty()) joined += " / ";
    joined += line;
  }
  return joined.empty() ? "(no messages)" : printable(joined, 1500);
}

// Signals that end brdfbake (the CLI's interrupt handler), held back while a child is started and
// registered, so an interrupt never leaves an unregistered gnuplot writing a temporary.
class HeldInterrupts {
 public:
  HeldInterrupts() {
    sigemptyset(&held_);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&held_, s);
    pthread_sigmask(SIG_BLOCK, &held_, &old_);
  }
  ~HeldInterrupts() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  HeldInterrupts(const HeldInterrupts&) = delete;
  HeldInterrupts& operator=(const HeldInterrupts&) = delete;
  const sigset_t& previous() const { return old_; }

 private:
  sigset_t held_, old_;
};

struct SpawnSetup {
  SpawnSetup() {
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attributes);
  }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
  }
  SpawnSetup(const SpawnSetup&) = delete;
  SpawnSetup& operator=(const SpawnSetup&) = delete;
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
};

// Starts gnuplot on `scriptFile` with stderr to `log`; returns its wait status. The child gets the
// default handling of every signal and the caller's signal mask.
int runChild(const fs::path& gnuplot, const fs::path& scriptFile, const fs::path& log) {
  SpawnSetup setup;
  posix_spawn_file_actions_addopen(&setup.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&setup.actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&setup.actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  sigset_t all;
  sigfillset(&all);
  posix_spawnattr_setsigdefault(&setup.attributes, &all);
  const std::string program = gnuplot.string(), script = scriptFile.string();
  char* const argv[] = {const_cast<char*>(program.c_str()), const_cast<char*>(script.c_str()), nullptr};
  pid_t pid = 0;
  int slot = -1;
  {
    const HeldInterrupts held;
    posix_spawnattr_setsigmask(&setup.attributes, &held.previous());
    posix_spawnattr_setflags(&setup.attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    const int error = posix_spawn(&pid, program.c_str(), &setup.actions, &setup.attributes, argv, environ);
    if (error != 0) {
      throw Error(Error::Kind::Io, "cannot run gnuplot (" + printable(program) + "): " + errnoText(error));
    }
    slot = registerChildProcess(pid);
  }
  int status = 0;
  pid_t waited = 0;
  do {
    waited = ::waitpid(pid, &status, 0);
  } while (waited < 0 && errno == EINTR);
  unregisterChildProcess(slot);
  if (waited < 0) throw Error(Error::Kind::Io, "gnuplot: cannot wait for it: " + errnoText(errno));
  return status;
}

// Throws Error(Io) unless `file` is a complete PNG or SVG as gnuplot writes them.
void requireCompleteChart(const fs::path& file, const fs::path& output) {
  const std::string shown = printable(output.string());
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size == 0) throw Error(Error::Kind::Io, shown + ": gnuplot wrote nothing");
  const std::string bytes = readTextFile(file, "chart", std::uintmax_t{1} << 30);
  const std::string ext = output.extension().string();
  bool complete = true;
  if (ext == ".png") {
    static const std::string kSignature = "\x89PNG\r\n\x1a\n";
    static const std::string kEnd("IEND\xae\x42\x60\x82", 8);
    complete = bytes.compare(0, kSignature.size(), kSignature) == 0 && bytes.size() >= 20 &&
               bytes.compare(bytes.size() - kEnd.size(), kEnd.size(), kEnd) == 0;
  } else if (ext == ".svg") {
    const std::size_t end = bytes.rfind("</svg>");
    complete = end != std::string::npos && bytes.find_first_not_of(" \t\r\n", end + 6) == std::string::npos;
  }
  if (!complete) {
    throw Error(Error::Kind::Io, shown + ": gnuplot wrote an incomplete " + ext.substr(1) + " (" +
                                     std::to_string(bytes.size()) + " bytes; is the disk full?)");
  }
}

}  // namespace

std::optional<fs::path> findGnuplot() {
  if (const char* forced = std::getenv("BRDFBAKE_GNUPLOT")) {
    if (*forced == '\0' || !executableFile(forced)) return std::nullopt;
    return fs::path(forced);
  }
  return onPath();
}

std::string gnuplotMissingReason() {
  if (const char* forced = std::getenv("BRDFBAKE_GNUPLOT")) {
    if (*forced == '\0') return "BRDFBAKE_GNUPLOT is empty (charts are off)";
    std::error_code ec;
    const std::string shown = "BRDFBAKE_GNUPLOT=" + printable(forced);
    if (!fs::exists(forced, ec)) return shown + ": no such file";
    if (!executableFile(forced)) return shown + ": not an executable file";
    return shown + " is usable";
  }
  return onPath() ? "gnuplot is on PATH" : "gnuplot not found on PATH (Debian: apt-get install gnuplot-nox)";
}

std::string gnuplotQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'')
      quoted += "''";
    else if (c != '\n')
      quoted += c;
  }
  return quoted + "'";
}

void runGnuplot(const std::string& script) {
  const auto gnuplot = findGnuplot();
  if (!gnuplot) throw Error(Error::Kind::InvalidArgument, gnuplotMissingReason() + "; charts need gnuplot");
  // The script goes through a file (no pipe that could break if gnuplot stops early).
  const ScratchFile scriptScratch(".gp"), errorsScratch(".log");
  writeFileAtomically(scriptScratch.path(), script);
  const int status = runChild(*gnuplot, scriptScratch.path(), errorsScratch.path());
  if (status != 0) {
    throw Error(Error::Kind::Io, "gnuplot " + describeWaitStatus(status) + ": " + readMessages(errorsScratch.path()));
  }
}

void renderGnuplotOutput(const fs::path& output, const std::function<std::string(const fs::path&)>& script) {
  AtomicOutput file(output);
  try {
    runGnuplot(script(file.temporaryPath()));
  } catch (const Error& e) {
    throw Error(e.kind(), printable(output.string()) + ": " + e.what());
  }
  requireCompleteChart(file.temporaryPath(), output);
  file.commit();
}

void checkChartPath(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".svg") {
    throw Error(Error::Kind::InvalidArgument, printable(output.string()) + ": a chart must be .png or .svg");
  }
}

void renderChart(const std::string& body, const fs::path& output) { renderChart(std::vector{body}, output); }

void renderChart(const std::vector<std::string>& panels, const fs::path& output) {
  checkChartPath(output);
  const std::string size = "size 900," + std::to_string(600 * std::max<std::size_t>(1, panels.size()));
  const std::string terminal =
      (output.extension() == ".png" ? "set terminal pngcairo " : "set terminal svg ") + size + " noenhanced\n";
  std::string body = panels.size() == 1 ? panels.front() : "";
  if (panels.size() > 1) {
    body = "set multiplot layout " + std::to_string(panels.size()) + ",1\n";
    for (const auto& panel : panels) body += "reset\n" + panel + "\n";
    body += "unset multiplot\n";
  }
  renderGnuplotOutput(output, [&](const fs::path& temporary) {
    return terminal + "set output " + gnuplotQuote(temporary.string()) + "\n" + body + "\nset output\n";
  });
}

}  // namespace brdfbake
