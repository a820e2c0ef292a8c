// No folder of the machine that made a file travels in it: every command, given its inputs by absolute
// paths under a folder with a name found nowhere else, writes files whose bytes (image attributes, KTX2
// key/value data, sidecars, fit.json, SH JSON) hold the inputs' file names but never that folder.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::q;
using test::runCli;

// Every file under `folder` whose bytes hold `text`.
std::vector<fs::path> filesHolding(const fs::path& folder, const std::string& text) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.find(text) != std::string::npos) found.push_back(entry.path());
  }
  return found;
}

TEST(NoMachinePaths, OutputsNameTheirInputsByFileNameOnly) {
  test::TempDir dir;
  const fs::path inputs = dir / "private_folder_4729";  // the name to look for
  fs::create_directories(inputs);
  for (const char* file : {"environments/sky_latlong.exr", "materials/gold.json", "tables/synthetic_two_lobes.astm",
                           "fits/synthetic_two_lobes.json"}) {
    fs::copy_file(test::sourcePath(std::string("data_samples/") + file), inputs / fs::path(file).filename());
  }
  const fs::path sky = inputs / "sky_latlong.exr", out = dir / "out";
  std::ofstream(inputs / "spec.json") << R"({"maps": [
    {"output": ")" << (out / "spec_phong.exr").string()
                                      << R"(", "parameterization": "paraboloid", "resolution": 16,
     "environment": {"file": ")" << sky.string()
                                      << R"(", "lobe": "phong:20"}},
    {"output": ")" << (out / "spec_lobes.exr").string()
                                      << R"(", "parameterization": "sphere", "resolution": 16,
     "material": {"model": "lobes", "mode": "lighting", "file": ")"
                                      << (inputs / "synthetic_two_lobes.json").string() << R"("},
     "lights": [{"direction": "eye", "color": [1, 1, 1]}]}]})";
  const std::string commands[] = {
      "matcap " + q(inputs / "gold.json") + " " + q(sky) + " --resolution 16 -o " + q(out / "gold.exr") + " -o " +
          q(out / "gold.png") + " -o " + q(out / "gold.ktx2"),
      "prefilter " + q(sky) + " --lobe irradiance --to cube --resolution 8 --sh-output " + q(out / "sh.json") + " -o " +
          q(out / "irr.dds"),
      "ibl " + q(sky) + " --out-dir " + q(out / "ibl") + " --resolution 8 --skybox-resolution 8 --dfg-size 8",
      "bake " + q(inputs / "spec.json") + " --out-dir " + q(out),
      "fit " + q(inputs / "synthetic_two_lobes.astm") + " --lobes 1 --held-out off -o " + q(out / "fit.json"),
      "convert " + q(out / "gold.exr") + " --to latlong --resolution 8 -o " + q(out / "gold_latlong.exr"),
      "preview " + q(out / "gold.exr") + " --resolution 16 -o " + q(out / "preview.png"),
  };
  for (const std::string& command : commands) {
    const auto result = runCli(command + " --quiet");
    ASSERT_EQ(result.exitCode, 0) << command << "\n" << result.output;
  }
  EXPECT_GE(std::distance(fs::recursive_directory_iterator(out), fs::recursive_directory_iterator()), 15);
  EXPECT_EQ(filesHolding(out, inputs.string()), std::vector<fs::path>{});
  EXPECT_EQ(filesHolding(out, dir.path().string()), std::vector<fs::path>{});
  // The names are there: what a file was made from is still said.
  EXPECT_FALSE(filesHolding(out, "sky_latlong.exr").empty());
}

}  // namespace
}  // namespace brdfbake
