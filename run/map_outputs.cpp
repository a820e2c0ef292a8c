#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/run/map_outputs.hpp>

#include <algorithm>

namespace brdfbake {
namespace fs = std::filesystem;

void MapOutputs::validate() const {
  requireField(!files.empty(), "outputs", "name at least one file");
  requireField(files.size() <= kMaxOutputs, "outputs",
               "at most " + std::to_string(kMaxOutputs) + " files per map, got " + std::to_string(files.size()));
  bool anyTexture = false;
  for (std::size_t i = 0; i < files.size(); ++i) {
    requireField(!files[i].empty(), "outputs", "an empty file name");
    try {
      anyTexture = isTextureContainer(imageFormatFor(files[i])) || anyTexture;
    } catch (const Error& e) {
      throw Error::invalidField("outputs", e.what());
    }
    for (std::size_t j = 0; j < i; ++j)
      requireField(!sameFile(files[i], files[j]), "outputs",
                   printable(files[i].string()) + " is named twice; each output is written once");
  }
  requireField(!texelFormat || anyTexture, "texel_format",
               "applies to .ktx2, .ktx and .dds outputs only; none of the outputs is one");
}

WriteOptions MapOutputs::writeOptionsFor(std::size_t i) const {
  WriteOptions options;
  options.inputs = inputs;
  if (isTextureContainer(imageFormatFor(files.at(i)))) options.texelFormat = texelFormat;
  return options;
}

std::string MapOutputs::names() const {
  std::string text;
  for (const fs::path& file : files) text += (text.empty() ? "" : ", ") + file.string();
  return text;
}

void checkJobFiles(const std::vector<FilePlan::Entry>& inputs, const std::vector<FilePlan::Entry>& outputs,
                   const std::optional<fs::path>& folder) {
  FilePlan plan(folder);
  for (const auto& input : inputs) plan.addInput(input.file, input.role);
  for (const auto& output : outputs) plan.addOutput(output.file, output.role);
  plan.check();
}

}  // namespace brdfbake
