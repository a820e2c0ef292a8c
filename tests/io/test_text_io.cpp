// Line files read with bounds, and stdout written with every write checked (core/text_io.hpp).
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/text_io.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::errorOf;
using test::put;

TEST(ReadTextLines, SplitsLinesOfEitherEnding) {
  test::TempDir dir;
  put(dir / "pairs.txt", "0 0 0 0\r\n# comment\n\n1 2 3 4");
  const std::vector<std::string> lines = readTextLines(dir / "pairs.txt", "--pairs file");
  EXPECT_EQ(lines, (std::vector<std::string>{"0 0 0 0", "# comment", "", "1 2 3 4"}));
  put(dir / "empty.txt", "");
  EXPECT_TRUE(readTextLines(dir / "empty.txt", "--dirs file").empty());
}

TEST(ReadTextLines, FilesThatNeverEndAreRefusedAtOnce) {
  test::TempDir dir;
  EXPECT_NE(errorOf([&] { readTextLines("/dev/zero", "--pairs file"); }, Error::Kind::Io)
                .find("/dev/zero: is a character device, not a regular file (--pairs file)"),
            std::string::npos);
  // A FIFO without a writer: refused, not waited on.
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  EXPECT_NE(errorOf([&] { readTextLines(dir / "fifo", "--dirs file"); }, Error::Kind::Io).find("is a FIFO"),
            std::string::npos);
}

TEST(ReadTextLines, BoundsNameTheFileAndLine) {
  test::TempDir dir;
  put(dir / "long.txt", "1 2 3\n" + std::string(5000, '7') + "\n");
  EXPECT_EQ(errorOf([&] { readTextLines(dir / "long.txt", "--pairs file"); }, Error::Kind::InvalidInput),
            (dir / "long.txt").string() + ":2: longer than 4096 bytes (--pairs file; docs/limits.md)");
  LineFileLimits small;
  small.maxBytes = 100;
  small.maxLines = 3;
  put(dir / "big.txt", std::string(101, '\n'));
  EXPECT_NE(errorOf([&] { readTextLines(dir / "big.txt", "--dirs file", small); }, Error::Kind::InvalidInput)
                .find("big.txt: more than 100 bytes (--dirs file"),
            std::string::npos);
  put(dir / "many.txt", "a\nb\nc\nd\n");
  EXPECT_NE(errorOf([&] { readTextLines(dir / "many.txt", "--dirs file", small); }, Error::Kind::InvalidInput)
                .find("many.txt: more than 3 lines"),
            std::string::npos);
}

// Runs writeStdout("report\n") with file descriptor 1 replaced by `fd` (or closed, fd < 0), and
// returns the error message ("" when it wrote).
std::string writeStdoutTo(int fd) {
  std::fflush(stdout);
  std::cout.flush();
  const int saved = ::dup(STDOUT_FILENO);
  if (fd >= 0)
    ::dup2(fd, STDOUT_FILENO);
  else
    ::close(STDOUT_FILENO);
  std::string message;
  try {
    writeStdout("report\n");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Io);
    message = e.what();
  }
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  return message;
}

TEST(WriteStdout, AFullDiskIsAnError) {
  const int full = ::open("/dev/full", O_WRONLY);
  if (full < 0) GTEST_SKIP() << "no /dev/full";
  EXPECT_EQ(writeStdoutTo(full), "stdout: write failed (No space left on device)");
  ::close(full);
}

TEST(WriteStdout, AClosedStdoutIsAnError) {
  EXPECT_EQ(writeStdoutTo(-1), "stdout: write failed (Bad file descriptor)");
}

TEST(WriteStdout, AReaderThatHasGoneIsAnErrorNotADeath) {
  int pipeEnds[2];
  ASSERT_EQ(::pipe(pipeEnds), 0);
  ::close(pipeEnds[0]);
  EXPECT_EQ(writeStdoutTo(pipeEnds[1]), "stdout: write failed (Broken pipe)");
  ::close(pipeEnds[1]);
  sigset_t pending;
  sigemptyset(&pending);
  ASSERT_EQ(sigpending(&pending), 0);
  EXPECT_EQ(sigismember(&pending, SIGPIPE), 0);  // consumed, not left to kill the process later
}

TEST(WriteStdout, WritesEveryByte) {
  test::TempDir dir;
  const int file = ::open((dir / "out.txt").c_str(), O_WRONLY | O_CREAT, 0600);
  ASSERT_GE(file, 0);
  EXPECT_EQ(writeStdoutTo(file), "");
  ::close(file);
  std::ifstream in(dir / "out.txt");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "report\n");
}

// What TextProgress writes to a file (not a terminal) for `reports`.
std::string progressText(const std::vector<std::pair<std::string, double>>& reports, bool enabled = true) {
  test::TempDir dir;
  const int file = ::open((dir / "log.txt").c_str(), O_WRONLY | O_CREAT, 0600);
  {
    TextProgress progress(enabled, file);
    const ProgressSink sink = progress.sink();
    EXPECT_EQ(static_cast<bool>(sink), enabled);
    for (const auto& [task, fraction] : reports)
      if (sink) sink(task, fraction);
  }
  ::close(file);
  std::ifstream in(dir / "log.txt");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(TextProgress, PlainLinesNameEachTaskItsStartAndItsEnd) {
  // Reports within a second of the start print no quarter lines: only each task's start and end.
  const std::string text = progressText({{"maps[0] a.exr", 0.0},
                                         {"maps[0] a.exr", 0.3},
                                         {"maps[0] a.exr", 0.6},
                                         {"maps[0] a.exr", 1.0},
                                         {"fit \x1b[2J", 1.0}});
  EXPECT_EQ(text, "brdfbake: maps[0] a.exr: 0 %\nbrdfbake: maps[0] a.exr: done\nbrdfbake: fit \\x1b[2J: done\n");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
  EXPECT_EQ(progressText({{"task", 0.5}}, /*enabled=*/false), "");
}

}  // namespace
}  // namespace brdfbake

TEST(FormatG, PrintsSignificantDigitsLikePrintfG) {
  // The expected strings are what C's printf("%.3g") and ("%.5g") print for these values.
  EXPECT_EQ(brdfbake::formatG(0.12634), "0.126");
  EXPECT_EQ(brdfbake::formatG(1234.5), "1.23e+03");
  EXPECT_EQ(brdfbake::formatG(2.0), "2");
  EXPECT_EQ(brdfbake::formatG(0.000123456, 5), "0.00012346");
}
