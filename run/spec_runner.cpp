#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <algorithm>
#include <sstream>

#include "map_runners.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
using namespace run_detail;

namespace {

// Outputs go under outDir when given (an absolute output keeps only its file name).
fs::path placed(const fs::path& outDir, const fs::path& written) {
  return outDir / (written.is_absolute() ? written.filename() : written);
}

void placeOutputs(BakeSpec& spec, const fs::path& outDir) {
  if (outDir.empty()) return;
  for (auto& map : spec.maps) {
    if (map.outputList) {
      const nlohmann::json& list = map.raw.at("outputs");
      map.output = placed(outDir, list.at(0).get<std::string>());
      for (std::size_t i = 1; i < list.size(); ++i) map.moreOutputs[i - 1] = placed(outDir, list[i].get<std::string>());
    } else {
      map.output = placed(outDir, map.raw.at("output").get<std::string>());
    }
    auto* e = std::get_if<EnvironmentMapSpec>(&map.content);
    if (e && e->shOutput) e->shOutput = placed(outDir, map.raw["environment"]["sh_output"].get<std::string>());
  }
}

// Refuses oversize maps before any work, so a spec either bakes whole or writes nothing.
void checkMapSizes(const BakeSpec& spec, const JobOptions& options, const std::string& label) {
  const RunOptions limits;
  for (const auto& map : spec.maps) {
    if (map.anyAuto()) continue;  // auto candidates stay far below the limit
    const auto parameterization = makeParameterization(map.parameterization, map.resolution);
    const long long texels = static_cast<long long>(parameterization->width()) * parameterization->height();
    const std::string size =
        std::to_string(parameterization->width()) + " x " + std::to_string(parameterization->height());
    if (texels > limits.maxTexels && !options.allowLarge) {
      throw Error(Error::Kind::Resource, label + ": " + map.jsonPath + ": a " + size + " map needs " +
                                             formatBytes(static_cast<double>(texels) * 16.0) +
                                             "; lower its resolution or allow large maps (--allow-large)");
    }
    requireWithinMemoryBudget(static_cast<double>(texels) * 16.0, label + ": " + map.jsonPath + ": a " + size + " map");
  }
}

// The environments of prefiltered maps and of materials lit by one, read and checked before any work
// (null for other material maps); maps reading one file the same way share one copy.
std::vector<std::shared_ptr<const Environment>> loadEnvironments(const BakeSpec& spec) {
  std::vector<std::shared_ptr<const Environment>> environments(spec.maps.size());
  for (std::size_t i = 0; i < spec.maps.size(); ++i) {
    if (spec.maps[i].environmentLighting()) {
      environments[i] = std::make_shared<const Environment>(loadMapEnvironment(spec.maps[i]));  // names the key
      continue;
    }
    const EnvironmentMapSpec* e = spec.maps[i].environmentMap();
    if (!e) continue;
    for (std::size_t j = 0; j < i && !environments[i]; ++j) {
      const EnvironmentMapSpec* other = spec.maps[j].environmentMap();
      if (other && sameFile(other->file, e->file) && other->from == e->from) environments[i] = environments[j];
    }
    if (!environments[i])
      environments[i] = std::make_shared<const Environment>(loadEnvironment(e->file, EnvironmentLoadOptions{e->from}));
  }
  return environments;
}

MapResult runOneMap(const MapSpec& map, const std::shared_ptr<const Environment>& environment, const SpecPlan& plan,
                    const JobOptions& options) {
  MapRunContext context{options, {}};
  if (!plan.specFile.empty()) context.write.inputs.push_back(plan.specFile);
  return std::visit(Overloaded{[&](const EnvironmentMapSpec& e) {
                                 context.write.inputs.push_back(e.file);
                                 return runEnvironmentMap(map, e, *environment, context);
                               },
                               [&](const MaterialMapSpec& m) {
                                 if (!m.environment) return runMaterialMap(map, context);
                                 context.write.inputs.push_back(m.environment->file);
                                 return runUnderEnvironmentMap(map, *environment, context);
                               }},
                    map.content);
}

MapResult failedMap(const MapSpec& map, const Error& error) {
  MapResult result;
  result.jsonPath = map.jsonPath;
  result.output = map.output;
  result.error = error.what();
  result.entry = {{"output", map.output.string()}, {"status", "failed"}, {"error", result.error}};
  result.lines.push_back(map.jsonPath + " failed: " + result.error);
  return result;
}

}  // namespace

void SpecRunOptions::validate() const {
  JobOptions::validate();
  require(spec.empty() != document.is_null(), "give either a spec file or a spec document, not both or neither");
}

std::string MapResult::briefReport() const {
  std::string text;
  for (const auto& line : lines) text += line + "\n";
  return text;
}

int SpecRunResult::failed() const {
  int count = 0;
  for (const auto& map : maps) count += map.written ? 0 : 1;
  return count;
}

std::string SpecRunResult::briefReport() const {
  std::string text;
  for (const auto& map : maps) text += map.briefReport();
  return text + failureSummary();
}

std::string SpecRunResult::failureSummary() const {
  if (failed() == 0) return "";
  return std::to_string(failed()) + " of " + std::to_string(maps.size()) + " maps failed" +
         (failed() < static_cast<int>(maps.size()) ? "; the others were written\n" : "\n");
}

nlohmann::json SpecRunResult::toJson() const {
  nlohmann::json report = {{"spec", spec.string()}, {"maps", nlohmann::json::array()}};
  for (const auto& map : maps) report["maps"].push_back(map.entry);
  return report;
}

SpecPlan planSpec(const SpecRunOptions& options) {
  options.validate();
  SpecPlan plan;
  if (!options.spec.empty()) {
    plan.spec = loadBakeSpec(options.spec);
    plan.specFile = options.spec;
  } else {
    plan.spec = parseBakeSpec(options.document, "", options.label);
  }
  placeOutputs(plan.spec, options.outDir);
  const fs::path specFolder = plan.specFile.parent_path();
  if (!options.outDir.empty()) {
    plan.outputFolder = options.outDir;
  } else if (!plan.specFile.empty()) {
    plan.outputFolder = specFolder.empty() ? fs::path(".") : specFolder;
  }
  // Every file the spec reads and writes, checked against each other before any work.
  plan.files = planSpecFiles(plan.spec, plan.specFile, plan.outputFolder);
  plan.files.check();
  checkMapSizes(plan.spec, options, plan.specFile.empty() ? options.label : plan.specFile.string());
  return plan;
}

SpecRunResult runSpec(const SpecRunOptions& options) {
  const SpecPlan plan = planSpec(options);
  const std::vector<std::shared_ptr<const Environment>> environments = loadEnvironments(plan.spec);
  SpecRunResult result;
  result.spec = plan.specFile.empty() ? fs::path(options.label) : plan.specFile;
  for (std::size_t i = 0; i < plan.spec.maps.size(); ++i) {
    const MapSpec& map = plan.spec.maps[i];
    try {
      MapResult made = runOneMap(map, environments[i], plan, options);
      for (const auto& note : map.notes) {
        made.notes.push_back(note);
        made.entry["notes"].push_back(note);
        made.lines.push_back("  note: " + note);
      }
      result.files.insert(result.files.end(), made.files.begin(), made.files.end());
      result.maps.push_back(std::move(made));
    } catch (const Error& error) {
      if (!result.firstError) result.firstError = error;
      result.maps.push_back(failedMap(map, error));
    }
  }
  return result;
}

MapResult runOneMapSpec(const nlohmann::json& document, const std::string& label, const JobOptions& options) {
  SpecRunOptions run;
  static_cast<JobOptions&>(run) = options;
  run.document = document;
  run.label = label;
  SpecRunResult result = runSpec(run);
  if (result.firstError) throw *result.firstError;
  return std::move(result.maps.front());
}

namespace run_detail {

MapResult makeMapResult(const MapSpec& map, const EntryFacts& facts, std::vector<fs::path> files,
                        std::vector<std::string> notes) {
  MapResult result;
  result.jsonPath = map.jsonPath;
  result.output = map.output;
  result.written = true;
  result.entry = {{"output", map.output.string()},
                  {"status", "written"},
                  {"files", pathsToJson(files)},
                  {"parameterization", facts.parameterization},
                  {"resolution", facts.resolution},
                  {"width", facts.width},
                  {"height", facts.height},
                  {"bake_path", facts.bakePath},
                  {"bake_seconds", facts.bakeSeconds},
                  {"write_seconds", facts.writeSeconds},
                  {"notes", notes}};
  if (map.outputList) result.entry["outputs"] = pathsToJson(map.outputs());
  result.files = std::move(files);
  result.notes = std::move(notes);
  return result;
}

void appendWritten(MapWriteReport& into, const MapWriteReport& from) {
  into.files.insert(into.files.end(), from.files.begin(), from.files.end());
  for (const std::string& note : from.notes)
    if (std::find(into.notes.begin(), into.notes.end(), note) == into.notes.end()) into.notes.push_back(note);
}

void putOutputs(nlohmann::json& map, const fs::path& output, const std::vector<fs::path>& more,
                const std::optional<std::string>& texelFormat) {
  if (more.empty()) {
    map["output"] = output.string();
  } else {
    map["outputs"] = nlohmann::json::array({output.string()});
    for (const fs::path& file : more) map["outputs"].push_back(file.string());
  }
  if (texelFormat) map["texel_format"] = *texelFormat;
}

std::string outputNames(const MapSpec& map) {
  std::string names;
  for (const fs::path& file : map.outputs()) names += (names.empty() ? "" : ", ") + file.string();
  return names;
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace run_detail
}  // namespace brdfbake
