#pragma once
// The readers of tests/js (node with the npm packages ktx-parse and parse-dds), which share no code
// with brdfbake's writers, run as child processes; and the Vulkan specification's cube face table,
// typed from the specification, to place texel centres the way a GPU samples a cube texture.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace brdfbake::test {

inline std::filesystem::path jsDir() { return std::filesystem::path(BRDFBAKE_SOURCE_DIR) / "tests" / "js"; }

// True when node runs and tests/js/node_modules holds `package` (scripts/quickstart.sh test runs `npm ci`).
inline bool haveNodePackage(const std::string& package) {
  return run("node --version").exitCode == 0 &&
         std::filesystem::exists(jsDir() / "node_modules" / package / "package.json");
}

// What a test says when it skips for want of `package`.
inline std::string missingNodePackage(const std::string& package) {
  return "node or the npm package " + package + " is missing: run `npm ci` in " + jsDir().string() +
         " (scripts/quickstart.sh test does when npm is there); skipping the independent reader";
}

inline nlohmann::json directionsJson(const std::vector<Vec3>& directions) {
  nlohmann::json list = nlohmann::json::array();
  for (const Vec3& d : directions) list.push_back({d.x(), d.y(), d.z()});
  return list;
}

// Runs tests/js/SCRIPT FILE DIRECTIONS and returns the JSON it prints last (anything node prints
// before it, such as warnings, is skipped).
inline nlohmann::json runNodeReader(const std::string& script, const std::filesystem::path& file,
                                    const nlohmann::json& directions) {
  const CommandResult result =
      run("node '" + (jsDir() / script).string() + "' '" + file.string() + "' '" + directions.dump() + "'");
  EXPECT_EQ(result.exitCode, 0) << result.output;
  const std::size_t last = result.output.rfind("\n{");
  return nlohmann::json::parse(last == std::string::npos ? result.output : result.output.substr(last + 1));
}

// A KTX2 file read by ktx-parse and looked up at `directions` (tests/js/inspect_ktx2.mjs).
inline nlohmann::json inspectKtx2(const std::filesystem::path& file, const std::vector<Vec3>& directions) {
  return runNodeReader("inspect_ktx2.mjs", file, directionsJson(directions));
}

// The direction of the centre of texel (i, j) of cube face `face` (+X, -X, +Y, -Y, +Z, -Z) of size n,
// inverting the Vulkan specification's face selection table (sc, tc per face; s = (sc + 1) / 2).
inline Vec3 vulkanTexelCentre(int face, int i, int j, int n) {
  const double sc = 2.0 * (i + 0.5) / n - 1.0, tc = 2.0 * (j + 0.5) / n - 1.0;
  const Vec3 d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
  return d[face].normalized();
}

}  // namespace brdfbake::test
