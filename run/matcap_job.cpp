#include <brdfbake/core/files.hpp>
#include <brdfbake/core/json_text.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/run/matcap_job.hpp>

#include <cctype>
#include <fstream>

#include "map_runners.hpp"

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

bool startsWithBrace(const fs::path& path) {
  requireInputFile(path, "material file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Error::Kind::Io, shortenForMessage(path.string()) + ": cannot open");
  for (char c = 0; in.get(c);) {
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
  }
  return false;
}

// The "material" object MATERIAL stands for (see MatcapRequest::material).
nlohmann::json materialJson(const fs::path& path) {
  if (!startsWithBrace(path)) return {{"model", "measured"}, {"file", path.string()}, {"method", "fit"}};
  nlohmann::json document = readJsonFile(path);
  const std::string name = shortenForMessage(path.string());
  if (isFitFileJson(document)) return {{"model", "lobes"}, {"file", path.string()}};
  if (!document.is_object() || document.contains("maps")) {
    throw Error(Error::Kind::InvalidInput,
                name + ": " + (document.is_object() ? "a bake spec" : "not a JSON object") +
                    "; a material file holds one material object ({\"model\": \"cook_torrance\", ...}), a fit.json "
                    "or a measured table");
  }
  // A relative "file" in the material (a fit or table it reads) is relative to the material's folder.
  if (auto file = document.find("file"); file != document.end() && file->is_string()) {
    const fs::path referenced = file->get<std::string>();
    if (!referenced.empty() && referenced.is_relative()) *file = (path.parent_path() / referenced).string();
  }
  return document;
}

}  // namespace

nlohmann::json matcapSpec(const MatcapRequest& request) {
  nlohmann::json environment = {{"file", request.environment.string()}};
  if (request.method != "auto") environment["method"] = request.method;
  if (request.maxError != 0.01) environment["max_error"] = request.maxError;
  if (request.from) environment["from"] = *request.from;
  nlohmann::json map = {{"parameterization", request.parameterization},
                        {"resolution", request.resolution},
                        {"material", materialJson(request.material)},
                        {"environment", environment}};
  if (request.exposure != 0.0) map["exposure"] = request.exposure;
  run_detail::putOutputs(map, request.output, request.moreOutputs, request.texelFormat);
  if (request.samplesPerTexel != 16) map["samples_per_texel"] = request.samplesPerTexel;
  if (request.yaw || request.pitch)
    map["camera"] = {{"yaw", request.yaw.value_or(0.0)}, {"pitch", request.pitch.value_or(0.0)}};
  return {{"maps", nlohmann::json::array({map})}};
}

MapResult makeMatcap(const MatcapRequest& request, const JobOptions& options) {
  return runOneMapSpec(matcapSpec(request), "matcap", options);
}

}  // namespace brdfbake
