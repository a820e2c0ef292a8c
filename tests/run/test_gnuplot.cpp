// Charts through gnuplot (core/gnuplot.hpp): a child process the interrupt cleanup stops, failures
// in words, outputs that appear whole or not at all. Most cases use a stand-in gnuplot (a shell
// script named by BRDFBAKE_GNUPLOT); the last ones use the real one when it is installed.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <thread>

#include "test_support.hpp"
#include "tiny_filesystem.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::errorOf;
using test::GnuplotVariable;
using test::hiddenTemporaries;
using test::slurp;

// An executable shell script standing in for gnuplot; "$out" is the path its script's first
// "set output '...'" names.
fs::path fakeGnuplot(const test::TempDir& dir, const std::string& body) {
  const fs::path script = dir / "fake-gnuplot";
  std::ofstream(script) << "#!/bin/sh\nout=$(sed -n \"s/^set output '\\(.*\\)'$/\\1/p\" \"$1\" | head -1)\n"
                        << body << "\n";
  fs::permissions(script, fs::perms::owner_all);
  return script;
}

// Waits up to 10 s for `file` to hold a process id.
pid_t waitForPid(const fs::path& file) {
  for (int i = 0; i < 1000; ++i) {
    const std::string text = slurp(file);
    if (!text.empty() && text.back() == '\n') return static_cast<pid_t>(std::stol(text));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return -1;
}

// True once `pid` has gone (or is a zombie nobody waits for), within 5 s.
bool gone(pid_t pid) {
  for (int i = 0; i < 500; ++i) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(stat)), {});
    const auto close = text.rfind(')');
    if (text.empty() || (close != std::string::npos && text.substr(close + 2, 1) == "Z")) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST(Gnuplot, AMissingGnuplotSaysWhy) {
  test::TempDir dir;
  {
    const GnuplotVariable variable("/nonexistent/gnuplot");
    EXPECT_EQ(errorOf([] { runGnuplot("plot x"); }, Error::Kind::InvalidArgument),
              "BRDFBAKE_GNUPLOT=/nonexistent/gnuplot: no such file; charts need gnuplot");
  }
  {
    const GnuplotVariable variable("");
    EXPECT_EQ(errorOf([] { runGnuplot("plot x"); }, Error::Kind::InvalidArgument),
              "BRDFBAKE_GNUPLOT is empty (charts are off); charts need gnuplot");
  }
  std::ofstream(dir / "plain") << "not a program";
  const GnuplotVariable variable((dir / "plain").string());
  EXPECT_NE(errorOf([] { runGnuplot("plot x"); }, Error::Kind::InvalidArgument).find("plain: not an executable file"),
            std::string::npos);
}

TEST(Gnuplot, FailuresAreToldInWordsWithItsMessagesPrintable) {
  test::TempDir dir;
  const GnuplotVariable variable(
      fakeGnuplot(dir, "printf 'line 1: bad \\033[2J\\n\\nline 2: worse\\n' >&2\nexit 3").string());
  EXPECT_EQ(errorOf([] { runGnuplot("plot x"); }, Error::Kind::Io),
            "gnuplot exited with status 3: line 1: bad \\x1b[2J / line 2: worse");
  const GnuplotVariable killed(fakeGnuplot(dir, "kill -9 $$").string());
  EXPECT_EQ(errorOf([] { runGnuplot("plot x"); }, Error::Kind::Io),
            "gnuplot was killed by signal 9 (Killed): (no messages)");
}

TEST(Gnuplot, AnIncompletePictureIsNeverCommitted) {
  test::TempDir dir;
  std::ofstream(dir / "old.png") << "old";
  const GnuplotVariable png(fakeGnuplot(dir, "printf '\\211PNG\\r\\n\\032\\n' > \"$out\"").string());
  EXPECT_EQ(errorOf([&] { renderChart("plot x", dir / "old.png"); }, Error::Kind::Io),
            (dir / "old.png").string() + ": gnuplot wrote an incomplete png (8 bytes; is the disk full?)");
  EXPECT_EQ(slurp(dir / "old.png"), "old");
  const GnuplotVariable svg(fakeGnuplot(dir, "printf '<svg>\\n<path d=\"M 0 0\"' > \"$out\"").string());
  EXPECT_NE(errorOf([&] { renderChart("plot x", dir / "c.svg"); }, Error::Kind::Io).find("incomplete svg"),
            std::string::npos);
  const GnuplotVariable none(fakeGnuplot(dir, "exit 0").string());
  EXPECT_EQ(errorOf([&] { renderChart("plot x", dir / "n.svg"); }, Error::Kind::Io),
            (dir / "n.svg").string() + ": gnuplot wrote nothing");
  EXPECT_FALSE(fs::exists(dir / "c.svg"));
  EXPECT_FALSE(fs::exists(dir / "n.svg"));
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(Gnuplot, TheInterruptCleanupStopsARunningGnuplot) {
  test::TempDir dir;
  const GnuplotVariable variable(
      fakeGnuplot(dir, "echo $$ > '" + (dir / "pid").string() + "'\nexec sleep 60").string());
  std::string message;
  std::thread chart([&] {
    try {
      renderChart("plot x", dir / "chart.png");
    } catch (const Error& e) {
      message = e.what();
    }
  });
  const pid_t pid = waitForPid(dir / "pid");
  ASSERT_GT(pid, 0);
  removeTemporaryFilesNow();  // what the CLI's SIGINT handler calls
  chart.join();
  EXPECT_NE(message.find("gnuplot was killed by signal 9"), std::string::npos) << message;
  EXPECT_TRUE(gone(pid));
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(Gnuplot, SigintEndsAProcessDrawingAChart) {
  // A child process set up as the CLI is (its handler removes temporaries and exits 128 + N), drawing
  // with a slow gnuplot, interrupted from outside: it ends at once with 130, gnuplot with it.
  test::TempDir dir;
  const GnuplotVariable variable(
      fakeGnuplot(dir, "echo $$ > '" + (dir / "pid").string() + "'\nexec sleep 60").string());
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    struct sigaction action {};
    action.sa_handler = [](int signal) {
      removeTemporaryFilesNow();
      ::_exit(128 + signal);
    };
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    try {
      renderChart("plot x", dir / "chart.png");
    } catch (...) {
      ::_exit(1);
    }
    ::_exit(0);
  }
  const pid_t gnuplot = waitForPid(dir / "pid");
  ASSERT_GT(gnuplot, 0);
  ::kill(child, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(gone(gnuplot));
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(Gnuplot, RealGnuplotDrawsWholePictures) {
  const GnuplotVariable variable(std::nullopt);
  if (!findGnuplot()) GTEST_SKIP() << gnuplotMissingReason();
  test::TempDir dir;
  renderChart("plot x", dir / "a.png");
  renderChart(std::vector<std::string>{"plot x", "plot x*x"}, dir / "b.svg");
  const std::string png = slurp(dir / "a.png"), svg = slurp(dir / "b.svg");
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(Gnuplot, AFullDiskIsAnErrorNamingTheChart) {
  const GnuplotVariable variable(std::nullopt);
  if (!findGnuplot()) GTEST_SKIP() << gnuplotMissingReason();
  BRDFBAKE_REQUIRE_TINY_FILESYSTEM(disk, "200k");
  // Leave about 4 KB free: less than any 900 x 600 chart.
  std::ofstream(disk / "filler", std::ios::binary) << std::string(disk.freeBytes() - 4096, 'f');
  std::ofstream(disk / "r.png") << "old";
  const std::string message =
      errorOf([&] { renderChart("plot sin(x) with lines, cos(x) with points", disk / "r.png"); }, Error::Kind::Io);
  EXPECT_EQ(message.rfind((disk / "r.png").string() + ": ", 0), 0u) << message;
  EXPECT_EQ(slurp(disk / "r.png"), "old");
  EXPECT_EQ(hiddenTemporaries(disk.path()), 0);
}

}  // namespace
}  // namespace brdfbake
