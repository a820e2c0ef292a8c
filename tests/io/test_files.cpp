// The file-system rules: atomic outputs, temporaries removed on every path out, planned files
// checked against each other (through symlinks, "..", hard links) before any work.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/files.hpp>

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <fstream>

#include "test_support.hpp"
#include "tiny_filesystem.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::errorOf;
using test::hiddenTemporaries;
using test::put;
using test::slurp;

TEST(AtomicOutput, TheTargetAppearsOnlyOnCommit) {
  test::TempDir dir;
  put(dir / "out.txt", "old");
  {
    AtomicOutput out(dir / "out.txt");
    put(out.temporaryPath(), "new");
    EXPECT_EQ(slurp(dir / "out.txt"), "old");
    EXPECT_EQ(out.temporaryPath().extension(), ".txt");
    EXPECT_EQ(out.temporaryPath().parent_path(), dir.path());
    out.commit();
  }
  EXPECT_EQ(slurp(dir / "out.txt"), "new");
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(AtomicOutput, AnAbandonedWriteLeavesNothingAndKeepsTheOldFile) {
  test::TempDir dir;
  put(dir / "out.txt", "old");
  try {
    AtomicOutput out(dir / "out.txt");
    put(out.temporaryPath(), "half");
    throw std::runtime_error("failure while writing");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(slurp(dir / "out.txt"), "old");
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(AtomicOutput, InterruptCleanupRemovesRegisteredTemporaries) {
  test::TempDir dir;
  AtomicOutput a(dir / "a.exr"), b(dir / "sub" / "b.json");
  ScratchFile scratch(".gp");
  put(a.temporaryPath(), "a");
  put(b.temporaryPath(), "b");
  put(scratch.path(), "plot");
  ASSERT_EQ(hiddenTemporaries(dir.path()), 1);
  removeTemporaryFilesNow();  // what the CLI's signal handler does
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
  EXPECT_EQ(hiddenTemporaries(dir / "sub"), 0);
  EXPECT_FALSE(fs::exists(scratch.path()));
}

TEST(AtomicOutput, AFolderAsTargetIsAClearError) {
  test::TempDir dir;
  fs::create_directories(dir / "out.exr");
  const std::string message = errorOf([&] { AtomicOutput out(dir / "out.exr"); }, Error::Kind::Io);
  EXPECT_NE(message.find("is a folder; give an output file name"), std::string::npos) << message;
}

TEST(WriteFileAtomically, CreatesTheFolderAndWritesTheBytes) {
  test::TempDir dir;
  writeFileAtomically(dir / "a" / "b" / "c.json", "{}\n");
  EXPECT_EQ(slurp(dir / "a" / "b" / "c.json"), "{}\n");
}

TEST(RequireInputFile, NamesMissingFilesAndFolders) {
  test::TempDir dir;
  put(dir / "t.astm", "12345");
  EXPECT_EQ(requireInputFile(dir / "t.astm"), 5u);
  EXPECT_NE(errorOf([&] { requireInputFile(dir / "none.astm", "table"); }, Error::Kind::Io)
                .find("none.astm: no such file (table)"),
            std::string::npos);
  EXPECT_NE(
      errorOf([&] { requireInputFile(dir.path(), "spec"); }, Error::Kind::Io).find(": is a folder, not a file (spec)"),
      std::string::npos);
}

TEST(ShortenForMessage, ElidesTheMiddleOfLongText) {
  EXPECT_EQ(shortenForMessage("short"), "short");
  const std::string huge(50'000'000, 'x');
  const std::string shown = shortenForMessage(huge);
  EXPECT_LT(shown.size(), 260u);
  EXPECT_NE(shown.find("(50000000 bytes)"), std::string::npos);
}

TEST(RequireInputFile, DevicesFifosAndSocketsAreRefusedWithoutBlocking) {
  test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  EXPECT_NE(errorOf([&] { readTextFile(dir / "fifo", "spec"); }, Error::Kind::Io).find("fifo: is a FIFO (named pipe)"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { readTextFile("/dev/zero", "table"); }, Error::Kind::Io)
                .find("/dev/zero: is a character device, not a regular file (table)"),
            std::string::npos);
}

TEST(ReadTextFile, NamesAreShownPrintable) {
  test::TempDir dir;
  const std::string message = errorOf([&] { readTextFile(dir / "a\x1b[2Jb\nbrdfbake: forged.json"); }, Error::Kind::Io);
  EXPECT_NE(message.find("a\\x1b[2Jb\\x0abrdfbake: forged.json: no such file"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(ReadTextFile, TheLimitHoldsWhateverTheSizeSaid) {
  test::TempDir dir;
  put(dir / "big.txt", std::string(5000, 'x'));
  EXPECT_EQ(readTextFile(dir / "big.txt", "text", 5000).size(), 5000u);
  EXPECT_NE(errorOf([&] { readTextFile(dir / "big.txt", "text", 4999); }, Error::Kind::Resource).find("4999 bytes"),
            std::string::npos);
}

// ---- outputs replace only regular files -----------------------------------------------------------

TEST(AtomicOutput, NeverReplacesOrFollowsAnythingButARegularFile) {
  test::TempDir dir;
  put(dir / "victim.txt", "keep");
  fs::create_symlink(dir / "victim.txt", dir / "link.txt");
  ASSERT_EQ(::mkfifo((dir / "fifo.txt").c_str(), 0600), 0);
  const bool root = ::geteuid() == 0;
  if (root) {
    ASSERT_EQ(::mknod((dir / "null.txt").c_str(), S_IFCHR | 0600, makedev(1, 3)), 0);
  }
  struct Case {
    const char* name;
    const char* what;
  };
  std::vector<Case> cases = {{"link.txt", "is a symbolic link"}, {"fifo.txt", "is a FIFO (named pipe)"}};
  if (root) cases.push_back({"null.txt", "is a character device"});
  for (const Case& c : cases) {
    const std::string message = errorOf([&] { writeFileAtomically(dir / c.name, "new"); }, Error::Kind::Io);
    EXPECT_NE(message.find(std::string(c.name) + " " + c.what + "; brdfbake replaces only regular files"),
              std::string::npos)
        << message;
  }
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(slurp(dir / "victim.txt"), "keep");
  EXPECT_TRUE(fs::is_fifo(dir / "fifo.txt"));
  if (root) {
    EXPECT_TRUE(fs::is_character_file(dir / "null.txt"));
  }
  EXPECT_EQ(hiddenTemporaries(dir.path()), 0);
}

TEST(AtomicOutput, CommitChecksTheTargetAgain) {
  test::TempDir dir;
  AtomicOutput out(dir / "out.txt");
  out.write("data");
  ASSERT_EQ(::mkfifo((dir / "out.txt").c_str(), 0600), 0);  // appears while the output is written
  EXPECT_NE(errorOf([&] { out.commit(); }, Error::Kind::Io).find("is a FIFO"), std::string::npos);
  EXPECT_TRUE(fs::is_fifo(dir / "out.txt"));
}

TEST(AtomicOutput, AFullDiskIsAnErrorNamingTheOutputAndKeepsTheOldFile) {
  BRDFBAKE_REQUIRE_TINY_FILESYSTEM(disk, "200k");
  put(disk / "out.bin", "old");
  const std::string bytes(400 * 1024, 'x');  // twice what the disk holds
  const std::string message = errorOf([&] { writeFileAtomically(disk / "out.bin", bytes); }, Error::Kind::Io);
  EXPECT_EQ(message, (disk / "out.bin").string() + ": write failed: No space left on device (disk full)");
  EXPECT_EQ(slurp(disk / "out.bin"), "old");
  EXPECT_EQ(hiddenTemporaries(disk.path()), 0);
  EXPECT_GT(disk.freeBytes(), 150u * 1024);  // the temporary's blocks are free again
}

TEST(OutputBatch, ASetIsReplacedWholeOrNotAtAll) {
  // The ibl job's files (a chain, irradiance, skybox, DFG table): the disk fills on the last, and
  // the previous run's set must stay whole, not half replaced and then cleaned away.
  BRDFBAKE_REQUIRE_TINY_FILESYSTEM(disk, "200k");
  for (const char* name : {"a.bin", "b.bin", "c.bin"}) put(disk / name, std::string("old ") + name);
  const std::string small(40 * 1024, 's'), large(400 * 1024, 'l');
  const std::string message = errorOf(
      [&] {
        OutputBatch batch;
        writeFileAtomically(disk / "a.bin", small);
        writeFileAtomically(disk / "b.bin", small);
        writeFileAtomically(disk / "c.bin", large);  // more than the disk holds
        batch.commit();
      },
      Error::Kind::Io);
  EXPECT_EQ(message, (disk / "c.bin").string() + ": write failed: No space left on device (disk full)");
  for (const char* name : {"a.bin", "b.bin", "c.bin"}) EXPECT_EQ(slurp(disk / name), std::string("old ") + name);
  EXPECT_EQ(hiddenTemporaries(disk.path()), 0);
  {
    OutputBatch batch;
    writeFileAtomically(disk / "a.bin", small);
    writeFileAtomically(disk / "b.bin", "new b");
    EXPECT_EQ(slurp(disk / "a.bin"), "old a.bin");  // nothing moves before the batch commits
    batch.commit();
  }
  EXPECT_EQ(slurp(disk / "a.bin"), small);
  EXPECT_EQ(slurp(disk / "b.bin"), "new b");
  EXPECT_EQ(hiddenTemporaries(disk.path()), 0);
}

class FilePlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    put(dir / "table.astm", "data");
    fs::create_directories(dir / "sub");
    fs::create_symlink(dir / "table.astm", dir / "link.json");
    fs::create_hard_link(dir / "table.astm", dir / "hard.astm");
  }
  std::string planError(const fs::path& output, std::optional<fs::path> folder = std::nullopt) {
    FilePlan plan(folder);
    plan.addInput(dir / "table.astm", "table");
    plan.addOutput(output, "-o");
    return errorOf([&] { plan.check(); }, Error::Kind::InvalidArgument);
  }
  test::TempDir dir;
};

TEST_F(FilePlanTest, AnOutputIsNeverAnInputHoweverItIsSpelled) {
  for (const fs::path& output : {dir / "table.astm", dir / "link.json", dir / "sub" / ".." / "table.astm",
                                 dir / "hard.astm", dir / "." / "table.astm"}) {
    EXPECT_NE(planError(output).find("is the table (an input)"), std::string::npos) << output;
  }
}

TEST_F(FilePlanTest, ANulInAnyPathIsRefusedBeforeAnyWork) {
  // The system would cut "out.exr\0.png" at the NUL and write out.exr under another name.
  const fs::path cut = dir / std::string("out.exr\0.png", 12);
  EXPECT_NE(planError(cut).find("-o: " + (dir / "out.exr").string() + "\\x00.png: contains a NUL character"),
            std::string::npos)
      << planError(cut);
  EXPECT_NE(errorOf([&] { AtomicOutput out(cut); }, Error::Kind::InvalidArgument).find("contains a NUL character"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { requireInputFile(cut, "table"); }, Error::Kind::InvalidArgument).find("table: "),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

TEST_F(FilePlanTest, TwoOutputsNeverShareAFile) {
  FilePlan plan;
  plan.addOutput(dir / "fit.png", "-o");
  plan.addOutput(dir / "sub" / ".." / "fit.png", "--report");
  const std::string message = errorOf([&] { plan.check(); }, Error::Kind::InvalidArgument);
  EXPECT_NE(message.find("--report: "), std::string::npos) << message;
  EXPECT_NE(message.find("is also written as -o"), std::string::npos) << message;
}

TEST_F(FilePlanTest, OutputsStayInsideTheOutputFolder) {
  EXPECT_NE(planError(dir / "sub" / ".." / ".." / "x.exr", dir / "sub").find("lies outside the output folder"),
            std::string::npos);
  EXPECT_NE(planError(dir / "x.exr", dir / "sub").find("lies outside the output folder"), std::string::npos);
  fs::create_symlink(dir.path(), dir / "sub" / "escape");
  EXPECT_NE(planError(dir / "sub" / "escape" / "x.exr", dir / "sub").find("lies outside"), std::string::npos);
  FilePlan inside(dir / "sub");
  inside.addOutput(dir / "sub" / "deeper" / "x.exr", "-o");
  EXPECT_NO_THROW(inside.check());
  // An output folder that is itself a link is followed: the outputs lie inside its target.
  fs::create_symlink(dir / "sub", dir / "linked");
  FilePlan linked(dir / "linked");
  linked.addOutput(dir / "linked" / "x.exr", "-o");
  EXPECT_NO_THROW(linked.check());
  EXPECT_NE(planError(dir / "linked" / ".." / "x.exr", dir / "linked").find("lies outside"), std::string::npos);
}

TEST_F(FilePlanTest, OutputsMustBeWritableFiles) {
  EXPECT_NE(planError(dir / "sub").find("is a folder; give an output file name"), std::string::npos);
  EXPECT_NE(planError(dir / "table.astm" / "x.exr").find("is not a folder"), std::string::npos);
}

TEST_F(FilePlanTest, OutputsMustBeRegularFilesWithNamesTheSystemAccepts) {
  ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
  EXPECT_NE(planError(dir / "fifo.exr").find("-o: " + (dir / "fifo.exr").string() + " is a FIFO"), std::string::npos);
  fs::create_symlink(dir / "elsewhere.exr", dir / "dangling.exr");
  EXPECT_NE(planError(dir / "dangling.exr").find("is a symbolic link"), std::string::npos);
  const std::string longName(300, 'n');
  EXPECT_NE(planError(dir / (longName + ".exr")).find("has 304 bytes; the file system's limit is 255 (NAME_MAX)"),
            std::string::npos);
  fs::path deep = dir.path();
  for (int i = 0; i < 20; ++i) deep /= std::string(250, 'd');
  EXPECT_NE(planError(deep / "x.exr").find("(PATH_MAX)"), std::string::npos);
}

TEST(FilePlan, TwentyThousandOutputsAreCheckedAndACollisionIsNamed) {
  test::TempDir dir;
  FilePlan plan(dir.path());
  for (int i = 0; i < 20000; ++i)
    plan.addOutput(dir / ("m" + std::to_string(i) + ".exr"), "maps[" + std::to_string(i) + "]");
  plan.addOutput(dir / "sub" / ".." / "m7.exr", "maps[7] again");
  const std::string message = errorOf([&] { plan.check(); }, Error::Kind::InvalidArgument);
  EXPECT_NE(message.find("maps[7] again: "), std::string::npos) << message;
  EXPECT_NE(message.find("is also written as maps[7];"), std::string::npos) << message;
}

}  // namespace
}  // namespace brdfbake
