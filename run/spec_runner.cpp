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
    if (map.inMemory()) continue;
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
void checkMapSizes(const BakeSpec& spec, const Context& context, const std::string& label) {
  for (const auto& map : spec.maps) {
    if (map.anyAuto()) continue;  // auto candidates stay far below the limit
    const auto parameterization = makeParameterization(map.parameterization, map.resolution);
    context.requireImageSize(parameterization->width(), parameterization->height(), label + ": " + map.jsonPath);
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
                    const Context& runContext) {
  MapRunContext context{runContext, {}};
  if (!plan.specFile.empty()) context.write.inputs.push_back(plan.specFile);
  return std::visit(Overloaded{[&](const EnvironmentMapSpec& e) {
                                 context.write.inputs.push_back(e.file);
                                 return runEnvironmentMap(map, e, environment, context);
                               },
                               [&](const MaterialMapSpec& m) {
                                 if (!m.environment) return runMaterialMap(map, context);
                                 context.write.inputs.push_back(m.environment->file);
                                 return runUnderEnvironmentMap(map, environment, context);
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

SpecPlan planSpec(const SpecRunOptions& options, const Context& context) {
  options.validate();
  SpecPlan plan;
  if (!options.spec.empty()) {
    plan.spec = loadBakeSpec(options.spec, options.inMemory);
    plan.specFile = options.spec;
  } else {
    plan.spec = parseBakeSpec(options.document, "", options.label, options.inMemory);
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
  checkMapSizes(plan.spec, context, plan.specFile.empty() ? options.label : plan.specFile.string());
  return plan;
}

SpecRunResult runSpec(const SpecRunOptions& options, const Context& context) {
  const SpecPlan plan = planSpec(options, context);
  const std::vector<std::shared_ptr<const Environment>> environments = loadEnvironments(plan.spec);
  SpecRunResult result;
  result.spec = plan.specFile.empty() ? fs::path(options.label) : plan.specFile;
  for (std::size_t i = 0; i < plan.spec.maps.size(); ++i) {
    const MapSpec& map = plan.spec.maps[i];
    try {
      MapResult made = runOneMap(map, environments[i], plan, context);
      if (made.made) made.entry["status"] = "in_memory";
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

namespace run_detail {

std::string MapPlace::names() const {
  std::string text;
  for (const fs::path& file : files) text += (text.empty() ? "" : ", ") + file.string();
  return text;
}

std::string MapPlace::made() const {
  return files.empty() ? "made " + (jsonPath.empty() ? std::string("the map") : jsonPath) + " in memory"
                       : "wrote " + names();
}

MapPlace placeOf(const MapSpec& map) { return {map.jsonPath, map.outputs(), map.outputList}; }

MapOutputs outputsOf(const MapSpec& map, const std::vector<fs::path>& inputs) {
  MapOutputs outputs;
  outputs.files = map.outputs();
  outputs.layout = map.cubeLayout;
  outputs.texelFormat = map.texelFormat;
  outputs.inputs = inputs;
  return outputs;
}

nlohmann::json withoutFolders(nlohmann::json value) {
  if (value.is_object()) {
    for (auto& [key, item] : value.items()) {
      const bool named = key == "file" || key == "output" || key == "sh_output" || key == "fresnel_table_output";
      if (named && item.is_string()) {
        item = fs::path(item.get<std::string>()).filename().string();
      } else if (key == "outputs" && item.is_array()) {
        for (auto& file : item)
          if (file.is_string()) file = fs::path(file.get<std::string>()).filename().string();
      } else {
        item = withoutFolders(std::move(item));
      }
    }
  } else if (value.is_array()) {
    for (auto& item : value) item = withoutFolders(std::move(item));
  }
  return value;
}

MapResult makeMapResult(const MapPlace& place, const EntryFacts& facts, std::vector<fs::path> files,
                        std::vector<std::string> notes) {
  MapResult result;
  result.jsonPath = place.jsonPath;
  if (!place.files.empty()) result.output = place.files.front();
  result.written = true;
  result.entry = {{"output", result.output.string()},
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
  if (place.list) result.entry["outputs"] = pathsToJson(place.files);
  result.files = std::move(files);
  result.notes = std::move(notes);
  return result;
}

void appendWritten(MapWriteReport& into, const MapWriteReport& from) {
  into.files.insert(into.files.end(), from.files.begin(), from.files.end());
  for (const std::string& note : from.notes)
    if (std::find(into.notes.begin(), into.notes.end(), note) == into.notes.end()) into.notes.push_back(note);
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace run_detail
}  // namespace brdfbake
