// The tool as a front over the run layer: one flag vocabulary on every command, "did you mean" for
// a mistyped command or flag, progress on stderr also when it is not a terminal, --json everywhere.
#include <nlohmann/json.hpp>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using test::q;
using test::runCli;
namespace fs = std::filesystem;

const std::string kPhongSpec = test::sourcePath("data_samples/specs/phong_eye.json");
const std::string kTable = test::sourcePath("data_samples/tables/synthetic_two_lobes.astm");

TEST(Front, AMistypedCommandOrFlagGetsASuggestion) {
  const auto command = runCli("bak " + q(kPhongSpec));
  EXPECT_EQ(command.exitCode, 2);
  EXPECT_NE(command.err.find("did you mean 'bake'?"), std::string::npos) << command.err;
  const auto flag = runCli("bake --thread 2 " + q(kPhongSpec));
  EXPECT_EQ(flag.exitCode, 2);
  EXPECT_NE(flag.err.find("'--thread' is not a flag of 'bake'; did you mean '--threads'?"), std::string::npos)
      << flag.err;
  const auto far = runCli("bake --zzzzzz " + q(kPhongSpec));
  EXPECT_EQ(far.exitCode, 2);
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << "no suggestion for a word near nothing:\n" << far.err;
  EXPECT_NE(far.err.find("Run 'brdfbake bake --help'"), std::string::npos) << far.err;
  // No command at all: say what the first word is not, not CLI11's "A subcommand is required".
  const auto bogus = runCli("bogus");
  EXPECT_EQ(bogus.exitCode, 2);
  EXPECT_EQ(bogus.err.rfind("brdfbake: error: 'bogus' is not a command (bake, ", 0), 0u) << bogus.err;
  const auto version = runCli("-V");
  EXPECT_EQ(version.exitCode, 2);
  EXPECT_EQ(version.err.rfind("brdfbake: error: '-V' is not a flag of brdfbake itself (--help, --version)", 0), 0u)
      << version.err;
  EXPECT_EQ(runCli("--version").exitCode, 0);
}

TEST(Front, EveryCommandHasJsonAndEveryComputingCommandHasThreads) {
  const std::vector<std::string> commands = {"bake",   "prefilter", "chart",   "fit",     "eval",
                                             "sample", "info",      "convert", "preview", "interpolation"};
  const std::vector<std::string> computing = {"bake",    "prefilter", "chart",        "fit",
                                              "convert", "preview",   "interpolation"};
  for (const auto& command : commands) {
    const auto help = runCli(command + " --help");
    ASSERT_EQ(help.exitCode, 0) << command;
    EXPECT_NE(help.out.find("--json"), std::string::npos) << command;
    EXPECT_NE(help.out.find("--quiet"), std::string::npos) << command;
    if (std::find(computing.begin(), computing.end(), command) != computing.end()) {
      EXPECT_NE(help.out.find("--threads"), std::string::npos) << command;
    }
  }
}

TEST(Front, AFitInAScriptPrintsProgressLinesOnStderr) {
  // stderr is a file here, not a terminal: plain lines, the task's start and its end, no bar.
  test::TempDir dir;
  const auto r = runCli("fit " + q(kTable) + " --lobes 1 -o " + q(dir / "fit.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.err.find("brdfbake: fit synthetic_two_lobes.astm: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(": done\n"), std::string::npos) << r.err;
  // One timing per job: stdout's report; the progress lines carry none to contradict it.
  EXPECT_EQ(r.err.find(" s)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << "a terminal bar in a log";
  EXPECT_EQ(r.err.find("\033["), std::string::npos) << "terminal escapes in a log";
  const auto quiet = runCli("fit " + q(kTable) + " --lobes 1 --quiet -o " + q(dir / "fit2.json"));
  ASSERT_EQ(quiet.exitCode, 0) << quiet.output;
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(quiet.out, "");
}

TEST(Front, ProgressStaysOffStdoutSoJsonParses) {
  test::TempDir dir;
  const auto r = runCli("bake " + q(kPhongSpec) + " --json --out-dir " + q(dir.path()));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(r.out);
  ASSERT_EQ(report["maps"].size(), 2u);
  EXPECT_NE(r.err.find("maps[0] phong_eye.exr"), std::string::npos) << r.err;
}

TEST(Front, OldSpellingsStillWorkButAreNotOffered) {
  test::TempDir dir;
  ASSERT_EQ(runCli("bake " + q(kPhongSpec) + " --quiet --out-dir " + q(dir.path())).exitCode, 0);
  const fs::path map = dir / "phong_eye.exr";
  const auto old = runCli("preview " + q(map) + " --size 16 -o " + q(dir / "p.png") + " --quiet");
  EXPECT_EQ(old.exitCode, 0) << old.output;
  const auto help = runCli("preview --help");
  EXPECT_EQ(help.out.find("--size"), std::string::npos) << "a hidden alias is listed";
  EXPECT_NE(help.out.find("--resolution"), std::string::npos);
}

TEST(Front, OutputIsAlwaysAFileAndOutDirAFolder) {
  test::TempDir dir;
  const auto r = runCli("bake " + q(kPhongSpec) + " -o " + q(dir / "x.exr"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--out-dir"), std::string::npos) << r.err;
  EXPECT_TRUE(test::filesIn(dir.path()).empty());
}

}  // namespace
}  // namespace brdfbake
