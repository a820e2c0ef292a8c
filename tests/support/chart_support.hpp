#pragma once
// What the chart tests share (the library's in tests/run/test_run_chart.cpp, the tool's in
// tests/cli/test_chart_environment.cpp): the spec they sweep.
#include <filesystem>
#include <fstream>
#include <string>

namespace brdfbake::test {

/// Writes a one-map spec prefiltering `environment` with `lobe` into a 16-texel paraboloid map
/// "m.exr" (max_error 0.01); `extra` is appended after the map (",{...}" adds maps).
inline void writeChartSpec(const std::filesystem::path& path, const std::string& environment, const std::string& lobe,
                           const std::string& extra = "") {
  std::ofstream(path) << R"({"maps": [{"output": "m.exr", "parameterization": "paraboloid", "resolution": 16,
      "environment": {"file": ")"
                      << environment << R"(", "lobe": ")" << lobe << R"(", "max_error": 0.01}})" << extra << "]}";
}

}  // namespace brdfbake::test
