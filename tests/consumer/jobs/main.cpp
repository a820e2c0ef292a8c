// Runs a spec, charts it, prefilters an environment, shades a matcap and fits a table, each with one call to the
// installed run layer, and checks that each result's JSON is what the installed tool prints with
// --json for the same job (timings, which differ from run to run, and the folders aside).
// Arguments: SOURCE_DIR WORK_DIR (the tool is WORK_DIR/prefix/bin/brdfbake).
#include <brdfbake/run/chart.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/matcap_job.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace fs = std::filesystem;

namespace {

// Drops what differs between two runs of one job (timings, the Pareto front they decide), and
// writes both runs' folders as "DIR".
nlohmann::json normalised(const nlohmann::json& value, const std::string& a, const std::string& b) {
  if (value.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, item] : value.items()) {
      if (key.find("seconds") == std::string::npos && key != "pareto") out[key] = normalised(item, a, b);
    }
    return out;
  }
  if (value.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& item : value) out.push_back(normalised(item, a, b));
    return out;
  }
  if (!value.is_string()) return value;
  std::string text = value.get<std::string>();
  for (const std::string& folder : {a, b}) {
    for (std::size_t at = text.find(folder); at != std::string::npos; at = text.find(folder, at + 3)) {
      text.replace(at, folder.size(), "DIR");
    }
  }
  return text;
}

nlohmann::json runTool(const fs::path& tool, const std::string& arguments) {
  const std::string command = "'" + tool.string() + "' " + arguments + " --json 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  char buffer[4096];
  while (pipe && std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  if (!pipe || pclose(pipe) != 0) throw std::runtime_error("the tool failed: " + command);
  return nlohmann::json::parse(out);
}

bool same(const std::string& job, const nlohmann::json& library, const nlohmann::json& tool, const fs::path& a,
          const fs::path& b) {
  const nlohmann::json x = normalised(library, a.string(), b.string()), y = normalised(tool, a.string(), b.string());
  if (x == y) return true;
  std::cerr << job << ": the library and the tool differ\nlibrary: " << x.dump(1) << "\ntool: " << y.dump(1) << "\n";
  return false;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

}  // namespace

int main(int argc, char** argv) {
  using namespace brdfbake;
  if (argc < 3) return 2;
  const fs::path source = argv[1], work = argv[2], tool = work / "prefix" / "bin" / "brdfbake";
  const fs::path mine = work / "library", theirs = work / "tool";
  fs::create_directories(mine);
  fs::create_directories(theirs);
  const fs::path spec = source / "data_samples/specs/phong_eye.json";
  const fs::path sky = source / "data_samples/environments/sky_latlong.exr";
  const fs::path table = source / "data_samples/tables/synthetic_two_lobes.astm";
  bool ok = true;

  SpecRunOptions run;
  run.spec = spec;
  run.outDir = mine;
  ok &= same("bake", runSpec(run).toJson(), runTool(tool, "bake " + q(spec) + " --out-dir " + q(theirs)), mine, theirs);

  ChartOptions chart;
  chart.spec = spec;
  chart.resolutions = {16, 32};
  chart.samplesPerTexel = {1};
  chart.parameterizations = {ParameterizationKind::Sphere};
  chart.lookups = 500;
  ok &= same("chart", chartSpec(chart).toJson(),
             runTool(tool, "chart " + q(spec) +
                               " --resolution 16,32 --samples-per-texel 1 --parameterizations sphere "
                               "--lookups 500"),
             mine, theirs);

  PrefilterFiles prefilter;
  prefilter.environment = sky;
  prefilter.request.lobe = PrefilterLobe::phong(50);
  prefilter.request.parameterization = ParameterizationKind::Paraboloid;
  prefilter.request.resolution = 32;
  prefilter.outputs.files = {mine / "sky.exr"};
  ok &= same("prefilter", runPrefilter(prefilter).toJson(),
             runTool(tool, "prefilter " + q(sky) + " --lobe phong:50 --to paraboloid --resolution 32 -o " +
                               q(theirs / "sky.exr")),
             mine, theirs);

  const fs::path gold = source / "data_samples/materials/gold.json";
  MatcapFiles matcap;
  matcap.material = gold;
  matcap.environment = sky;
  matcap.request.resolution = 32;
  matcap.outputs.files = {mine / "gold.exr"};
  ok &= same("matcap", runMatcap(matcap).toJson(),
             runTool(tool, "matcap " + q(gold) + " " + q(sky) + " --resolution 32 -o " + q(theirs / "gold.exr")), mine,
             theirs);

  FitTableOptions fit;
  fit.table = table;
  fit.fit.lobes = 1;
  fit.output = mine / "fit.json";
  ok &= same("fit", fitTable(fit).toJson(),
             runTool(tool, "fit " + q(table) + " --lobes 1 -o " + q(theirs / "fit.json")), mine, theirs);
  if (!ok) return 1;
  std::printf("consumer: ok\n");
  return 0;
}
