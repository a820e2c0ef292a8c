// A map's outputs (docs/spec.md): "output" or "outputs", and "texel_format" for texture containers.
#include "map_outputs.hpp"

#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/map_mips.hpp>

namespace brdfbake {
namespace fs = std::filesystem;

namespace spec_detail {
namespace {

constexpr std::size_t kMaxPathLength = 4096;  // PATH_MAX on Linux
constexpr std::size_t kMaxNameLength = 255;   // NAME_MAX of Linux file systems
constexpr std::size_t kMaxOutputs = 16;       // files per map

// One output path: not empty, within the system's limits, of a format brdfbake writes.
fs::path parseOutputPath(const nlohmann::json& value, const std::string& path, const fs::path& baseDirectory) {
  if (!value.is_string()) throw specError(path, "must be a file name, got " + describe(value));
  const std::string output = value.get<std::string>();
  if (output.empty()) throw specError(path, "must not be empty");
  if (output.size() > kMaxPathLength) {
    throw specError(path, "a name of " + std::to_string(output.size()) + " characters; paths are limited to " +
                              std::to_string(kMaxPathLength));
  }
  for (const auto& part : fs::path(output)) {
    if (part.string().size() > kMaxNameLength) {
      throw specError(path, "a name of " + std::to_string(part.string().size()) +
                                " bytes in the path; file names are limited to " + std::to_string(kMaxNameLength) +
                                " (NAME_MAX)");
    }
  }
  try {
    imageFormatFor(output);
  } catch (const Error& e) {
    throw specError(path, e.what());
  }
  return fs::path(output).is_absolute() ? fs::path(output) : baseDirectory / output;
}

// A whole mip chain in each output file: a gloss chain or "mips" with "mip_layout": "tiled".
bool wholeChainInFile(const MapSpec& spec) {
  if (const EnvironmentMapSpec* e = spec.environmentMap()) return e->mipLayout == MipLayout::Tiled;
  const MaterialMapSpec* m = spec.materialMap();
  return m && m->mips && m->mipLayout == MipLayout::Tiled;
}

}  // namespace

void parseMapOutputs(JsonObjectReader& map, MapSpec& spec, const fs::path& baseDirectory, bool inMemory) {
  if (inMemory && !map.has("outputs") && !map.has("output")) return;
  if (!map.has("outputs")) {
    spec.output = parseOutputPath(map.require("output"), map.child("output"), baseDirectory);
    return;
  }
  if (map.has("output")) {
    throw specError(map.child("outputs"), "give \"output\" (one file) or \"outputs\" (several), not both");
  }
  const nlohmann::json& list = map.array("outputs", kMaxOutputs);
  if (list.empty()) throw specError(map.child("outputs"), "must name at least one file");
  spec.outputList = true;
  for (std::size_t i = 0; i < list.size(); ++i) {  // two on one file: parseBakeSpec refuses it
    const fs::path file = parseOutputPath(list[i], map.child("outputs") + "[" + std::to_string(i) + "]", baseDirectory);
    (i == 0 ? spec.output : spec.moreOutputs.emplace_back()) = file;
  }
}

void parseTexelFormatAndCheckOutputs(JsonObjectReader& map, MapSpec& spec) {
  const std::vector<fs::path> files = spec.outputs();
  if (map.has("texel_format")) {
    spec.texelFormat = map.parsed("texel_format", parseTexelFormat);
    const bool anyTexture = std::any_of(files.begin(), files.end(),
                                        [](const fs::path& file) { return isTextureContainer(imageFormatFor(file)); });
    if (!anyTexture) {
      throw specError(map.child("texel_format"),
                      "applies to .ktx2, .ktx and .dds outputs only; none of the map's outputs is one");
    }
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (const std::string problem = spec.outputProblem(i); !problem.empty())
      throw specError(spec.outputJsonPath(i), problem);
  }
}

void refuseFilesInMemory(const MapSpec& spec) {
  if (!spec.inMemory()) return;
  auto refuse = [&](const std::string& key, const std::string& what) {
    throw specError(spec.jsonPath + "." + key, what + ": name an \"output\" (a map made in memory writes no files)");
  };
  if (spec.radialProfile) refuse("parameterization", "a radial profile is read back from its file");
  if (const MaterialMapSpec* m = spec.materialMap()) {
    if (m->mips) refuse("mips", "mip levels are files beside the map's output");
    if (m->fresnelTableOutput) refuse("fresnel_table_output", "the Fresnel table is a file");
  }
  if (const EnvironmentMapSpec* e = spec.environmentMap()) {
    if (e->shOutput) refuse("environment.sh_output", "the SH coefficients are a file");
    if (e->fresnel) refuse("environment.fresnel", "the Fresnel maps are files beside the map's output");
    if (e->lobeModel() && e->lobeModel()->variesWithView())
      refuse("environment.lobe", "a lobe varying with the view makes one file per elevation");
  }
}

}  // namespace spec_detail

std::vector<fs::path> MapSpec::outputs() const {
  if (inMemory()) return {};
  std::vector<fs::path> files{output};
  files.insert(files.end(), moreOutputs.begin(), moreOutputs.end());
  return files;
}

std::string MapSpec::outputJsonPath(std::size_t i) const {
  return outputList ? jsonPath + ".outputs[" + std::to_string(i) + "]" : jsonPath + ".output";
}

WriteOptions MapSpec::writeOptionsFor(std::size_t i, std::vector<fs::path> readFiles) const {
  WriteOptions options;
  options.inputs = std::move(readFiles);
  if (isTextureContainer(imageFormatFor(outputs().at(i)))) options.texelFormat = texelFormat;
  return options;
}

std::string MapSpec::outputProblem(std::size_t i) const {
  const fs::path file = outputs().at(i);
  OutputShape shape;
  if (!radialProfile && !anyAuto()) {
    shape.parameterization = parameterization;
    shape.resolution = resolution;
  }
  shape.wholeChain = spec_detail::wholeChainInFile(*this);
  if (shape.wholeChain) shape.resolution = resolution;
  shape.cubeLayout = cubeLayout;
  shape.texelFormat = writeOptionsFor(i, {}).texelFormat;
  return containerProblem(file, shape);
}

}  // namespace brdfbake
