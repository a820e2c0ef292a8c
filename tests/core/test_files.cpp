// The file-system rules: atomic outputs, temporaries removed on every path out, planned files
// checked against each other (through symlinks, "..", hard links) before any work.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

int hiddenTemporaries(const fs::path& folder) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().filename().string().find(".tmp-") != std::string::npos) ++count;
  }
  return count;
}

template <typename F>
std::string errorOf(F&& f, Error::Kind expected) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), expected) << e.what();
    return e.what();
  }
  return "(no error)";
}

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
  EXPECT_NE(shown.find("(50000000 characters)"), std::string::npos);
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
}

TEST_F(FilePlanTest, OutputsMustBeWritableFiles) {
  EXPECT_NE(planError(dir / "sub").find("is a folder; give an output file name"), std::string::npos);
  EXPECT_NE(planError(dir / "table.astm" / "x.exr").find("is not a folder"), std::string::npos);
}

}  // namespace
}  // namespace brdfbake
