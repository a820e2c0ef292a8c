// Bad input as a new user (or an attacker) meets it, one test per case of the hardening issue:
// a clear error with the documented exit status, nothing lost, nothing left behind.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <thread>

#include "test_support.hpp"

extern char** environ;

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::put;
using test::q;
using test::runCli;
using test::slurp;

void putJson(const fs::path& p, const nlohmann::json& j) { put(p, j.dump(2)); }

nlohmann::json phongMap(const std::string& output, int resolution = 16) {
  return {{"output", output},
          {"parameterization", "sphere"},
          {"resolution", resolution},
          {"samples_per_texel", 1},
          {"material", {{"model", "phong"}, {"specular", {1, 1, 1}}, {"exponent", 20}}},
          {"lights", {{{"direction", "eye"}}}}};
}

using test::filesIn;

const fs::path kTable = test::sourcePath("data_samples/tables/synthetic_two_lobes.astm");

// 1. ------------------------------------------------------------------------------------------------
TEST(HostileInput, DeeplyNestedJsonIsRefusedWithFileAndPath) {
  test::TempDir dir;
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  put(dir / "spec.json", "{\"maps\":" + deep + "}");
  put(dir / "fit.json", "{\"format\": \"brdfbake.lobe_fit\", \"model\": " + deep + "}");
  put(dir / "material.json", "{\"model\": \"phong\", \"specular\": " + deep + "}");
  for (const auto& [command, file] : {std::pair{"bake ", "spec.json"},
                                      {"eval --wi 0,0,1 --wo 0,0,1 ", "fit.json"},
                                      {"eval --wi 0,0,1 --wo 0,0,1 ", "material.json"}}) {
    const auto r = runCli(command + q(dir / file));
    EXPECT_EQ(r.exitCode, 2) << file << ": " << r.output.substr(0, 300);
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output.substr(0, 300);
    EXPECT_NE(r.output.find("nested more than 64 levels deep"), std::string::npos) << r.output.substr(0, 300);
    EXPECT_LT(r.output.size(), 1000u);
  }
}

// 2. ------------------------------------------------------------------------------------------------
TEST(HostileInput, NoCommandOverwritesItsInputsOrWritesOneFileTwice) {
  test::TempDir dir;
  fs::copy_file(kTable, dir / "tab.astm");
  const std::string original = slurp(dir / "tab.astm");
  fs::create_directories(dir / "sub");
  fs::create_symlink(dir / "tab.astm", dir / "alias.json");
  const std::vector<std::string> attempts = {
      "fit " + q(dir / "tab.astm") + " -o " + q(dir / "tab.astm"),
      "fit " + q(dir / "tab.astm") + " --report " + q(dir / "tab.astm"),
      "fit " + q(dir / "tab.astm") + " -o " + q(dir / "alias.json"),
      "fit " + q(dir / "tab.astm") + " -o " + q(dir / "sub" / ".." / "tab.astm"),
      "fit " + q(dir / "tab.astm") + " -o " + q(dir / "same.png") + " --report " + q(dir / "same.png"),
  };
  for (const auto& a : attempts) {
    const auto r = runCli(a);
    EXPECT_EQ(r.exitCode, 2) << a << "\n" << r.output;
    EXPECT_EQ(r.output.find("fit "), std::string::npos) << "refused before fitting: " << r.output;
  }
  EXPECT_EQ(slurp(dir / "tab.astm"), original);
  EXPECT_FALSE(fs::exists(dir / "same.png"));

  // A spec whose output is its own measured table (tables are detected by content, so an ASTM
  // table may be called t.png), or whose output's metadata sidecar is its own lobes file.
  fs::copy_file(kTable, dir / "t.png");
  nlohmann::json measured = phongMap("t.png");
  measured["material"] = {{"model", "measured"}, {"file", "t.png"}, {"method", "mirror"}};
  measured.erase("lights");
  putJson(dir / "spec.json", {{"maps", {measured}}});
  auto r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("maps[0].output: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("is the maps[0].material.file (an input)"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir / "t.png"), original);

  fs::copy_file(test::sourcePath("data_samples/fits/synthetic_two_lobes.json"), dir / "fit.hdr.json");
  const std::string fit = slurp(dir / "fit.hdr.json");
  nlohmann::json lobes = phongMap("fit.hdr");
  lobes["material"] = {{"model", "lobes"}, {"file", "fit.hdr.json"}};
  lobes.erase("lights");
  putJson(dir / "spec.json", {{"maps", {lobes}}});
  r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("maps[0].output (metadata sidecar): "), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir / "fit.hdr.json"), fit);

  // ... or the spec itself, through its metadata sidecar name.
  putJson(dir / "s.exr.json", {{"maps", {phongMap("s.exr")}}});
  r = runCli("bake " + q(dir / "s.exr.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("(metadata sidecar)"), std::string::npos) << r.output;
}

// 4. ------------------------------------------------------------------------------------------------
// Starts the CLI, waits until a temporary of the output appears (the map is being written), then
// sends `signal`. Returns the wait status.
int interruptWhileWriting(const fs::path& spec, const fs::path& folder, int signal) {
  const std::string cli = BRDFBAKE_CLI;
  std::vector<std::string> args = {cli, "bake", spec.string(), "--quiet"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, (folder / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  EXPECT_EQ(posix_spawn(&pid, cli.c_str(), &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  const auto start = std::chrono::steady_clock::now();
  bool seen = false;
  while (!seen && std::chrono::steady_clock::now() - start < std::chrono::minutes(5)) {
    for (const auto& e : fs::directory_iterator(folder))
      seen = seen || e.path().filename().string().find(".tmp-") != std::string::npos;
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    int status = 0;
    if (!seen && waitpid(pid, &status, WNOHANG) == pid) return -1;  // finished before we saw it writing
  }
  EXPECT_TRUE(seen) << "never saw a temporary being written";
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

TEST(HostileInput, InterruptsRemoveTemporariesAndExitWith128PlusTheSignal) {
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) {
    test::TempDir dir;
    // A large map, so writing it takes long enough to be interrupted.
    putJson(dir / "spec.json", {{"maps", {phongMap("big.exr", 4096)}}});
    const int status = interruptWhileWriting(dir / "spec.json", dir.path(), signal);
    if (status == -1) GTEST_SKIP() << "the write finished before it could be interrupted";
    ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of handling it";
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    const std::string err = slurp(dir / "stderr.txt");
    EXPECT_NE(err.find("temporary files removed"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 2) << "one line after the progress line: " << err;
    EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"spec.json", "stderr.txt"}));
  }
}

// 5. ------------------------------------------------------------------------------------------------
TEST(HostileInput, HeaderSizesAreCheckedAgainstTheFileAndTheBudget) {
  test::TempDir dir;
  for (const auto& [name, size] : {std::pair{"small.hdr", "-Y 10000 +X 20000"}, {"huge.hdr", "-Y 100000 +X 200000"}}) {
    std::string header = std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n") + size + "\n";
    header.resize(60, '\0');
    put(dir / name, header);
    const auto r =
        runCli("prefilter " + q(dir / name) + " --lobe irradiance --to sphere --resolution 8 -o " + q(dir / "o.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("more than a 60-byte file can hold"), std::string::npos) << r.output;
  }
  putJson(dir / "spec.json", {{"maps", {phongMap("big.exr", 65536)}}});
  const auto r = runCli("bake --allow-large " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 4) << r.output;
  EXPECT_NE(r.output.find("a 65536 x 65536 map needs 64 GiB"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "big.exr"));
}

// 6. ------------------------------------------------------------------------------------------------
TEST(HostileInput, OutputsStayInsideTheOutputFolder) {
  test::TempDir dir;
  fs::create_directories(dir / "specs");
  putJson(dir / "specs" / "spec.json", {{"maps", {phongMap("../../x.exr")}}});
  auto r = runCli("bake " + q(dir / "specs" / "spec.json") + " --out-dir " + q(dir / "out"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("lies outside the output folder"), std::string::npos) << r.output;
  r = runCli("bake " + q(dir / "specs" / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"specs", "specs/spec.json"}));
}

// 7. ------------------------------------------------------------------------------------------------
TEST(HostileInput, EveryFileASpecWritesIsCheckedForCollisionsFirst) {
  test::TempDir dir;
  nlohmann::json cube = phongMap("c.exr");
  cube["parameterization"] = "cube";
  cube["layout"] = "faces";
  cube["view"] = {0, 0, 1};
  cube["lights"] = {{{"direction", {0, 0, 1}}}};
  putJson(dir / "spec.json", {{"maps", {phongMap("first.exr"), cube, phongMap("c_posx.exr")}}});
  const auto r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("maps[2].output: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("is also written as maps[1].output"), std::string::npos) << r.output;
  EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"spec.json"}) << "nothing baked before the check";
}

// 8. ------------------------------------------------------------------------------------------------
TEST(HostileInput, NumbersOutOfRangeNameTheFileAndPath) {
  test::TempDir dir;
  put(dir / "spec.json", R"({"maps": [{"output": "a.exr", "parameterization": "sphere", "resolution": 16,
    "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 1e400}, "lights": [{"direction": "eye"}]}]})");
  auto r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("spec.json: maps[0].material.exponent: number out of range"), std::string::npos) << r.output;

  // A huge but finite direction is a direction: it normalises without overflow.
  nlohmann::json map = phongMap("b.exr");
  map["lights"] = {{{"direction", {1e300, 1e300, 1e300}}}};
  putJson(dir / "spec.json", {{"maps", {map}}});
  r = runCli("bake " + q(dir / "spec.json") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "b.exr"));
}

// 9. ------------------------------------------------------------------------------------------------
TEST(HostileInput, MessagesSayWhatIsWrong) {
  test::TempDir dir;
  fs::create_directories(dir / "folder.exr");
  putJson(dir / "spec.json", {{"maps", {phongMap("folder.exr")}}});
  auto r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("folder.exr is a folder; give an output file name"), std::string::npos) << r.output;

  r = runCli("fit " + q(dir.path()));
  EXPECT_EQ(r.exitCode, 3) << r.output;
  EXPECT_NE(r.output.find("is a folder, not a file"), std::string::npos) << r.output;

  nlohmann::json fit = nlohmann::json::parse(slurp(test::sourcePath("data_samples/fits/synthetic_two_lobes.json")));
  fit.erase("format");
  putJson(dir / "fit.json", fit);
  r = runCli("eval " + q(dir / "fit.json") + " --wi 0,0,1 --wo 0,0,1");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("looks like a fit.json but has no \"format\""), std::string::npos) << r.output;

  putJson(dir / "spec.json", {{"maps", {phongMap(std::string(5'000'000, 'n') + ".exr")}}});
  r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_LT(r.output.size(), 1000u);
  EXPECT_NE(r.output.find("paths are limited to 4096"), std::string::npos) << r.output.substr(0, 500);
  // Beyond 16 MiB a JSON file is refused before it is parsed (docs/limits.md).
  putJson(dir / "spec.json", {{"maps", {phongMap(std::string(50'000'000, 'n') + ".exr")}}});
  r = runCli("bake " + q(dir / "spec.json"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("bytes of JSON, more than the 16 MiB accepted"), std::string::npos)
      << r.output.substr(0, 500);
}

TEST(HostileInput, NegativeMeasuredValuesAreClampedWithANote) {
  test::TempDir dir;
  std::string table = slurp(kTable);
  // Make one value negative: the last number of the first data row.
  const std::size_t rows = table.find("\n\n");
  const std::size_t lineEnd = table.find('\n', rows + 2);
  const std::size_t lastComma = table.rfind(',', lineEnd);
  table.replace(lastComma + 1, lineEnd - lastComma - 1, "-0.25");
  put(dir / "t.astm", table);
  nlohmann::json map = phongMap("m.exr");
  map["material"] = {{"model", "measured"}, {"file", "t.astm"}, {"method", "mirror"}};
  map.erase("lights");
  putJson(dir / "spec.json", {{"maps", {map}}});
  const auto r = runCli("bake " + q(dir / "spec.json") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(r.out);
  const std::string notes = report["maps"][0]["notes"].dump();
  EXPECT_NE(notes.find("maps[0].material.file: 1 negative RGB values clamped to 0 for baking"), std::string::npos)
      << notes;
}

// 10. -----------------------------------------------------------------------------------------------
TEST(HostileInput, AMapThatFailsWhileBakingDoesNotStopTheOthersAndIsReported) {
  test::TempDir dir;
  nlohmann::json unreachable = phongMap("auto.exr");
  unreachable["samples_per_texel"] = "auto";  // 16^2 texels, 1 to 64 samples: a quick search
  unreachable["max_error"] = 1e-9;            // no candidate can meet it: fails at bake time, after validation
  putJson(dir / "spec.json", {{"maps", {phongMap("one.exr"), unreachable, phongMap("three.exr")}}});
  const auto r = runCli("bake " + q(dir / "spec.json") + " --json");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  const auto report = nlohmann::json::parse(r.out.substr(0, r.output.rfind("}") + 1));
  ASSERT_EQ(report["maps"].size(), 3u);
  EXPECT_EQ(report["maps"][0]["status"], "written");
  EXPECT_EQ(report["maps"][1]["status"], "failed");
  EXPECT_NE(report["maps"][1]["error"].get<std::string>().find("no configuration meets max_error"), std::string::npos);
  EXPECT_EQ(report["maps"][2]["status"], "written");
  EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"one.exr", "spec.json", "three.exr"}));
}

}  // namespace
}  // namespace brdfbake
