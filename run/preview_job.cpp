#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/preview_job.hpp>

namespace brdfbake {

void PreviewJobOptions::validate() const {
  preview.validate();
  imageFormatFor(output);
}

PreviewResult makePreview(const PreviewJobOptions& options, const Context& context) {
  options.validate();
  FilePlan plan;
  plan.addInput(options.source.path, "map");
  for (const auto& f : mapOutputFiles(options.output, "output")) plan.addOutput(f.file, f.role);
  plan.check();
  const BakedOutput source = options.source.open();
  Image image = renderPreview(source, options.preview);
  context.checkCancelled();
  image.metadata = {{"preview_of", options.source.path.filename().string()},
                    {"object", std::string(toString(options.preview.object))},
                    {"per_vertex", options.preview.perVertex}};
  const WriteReport written =
      writeImage(image, options.output, {.inputs = {options.source.path}, .texelFormat = std::nullopt});
  return {{options.output}, written.notes};
}

std::string PreviewResult::briefReport() const {
  std::string text = "wrote " + files.front().string() + "\n";
  for (const auto& note : notes) text += "  note: " + note + "\n";
  return text;
}

nlohmann::json PreviewResult::toJson() const {
  return {{"output", files.front().string()}, {"files", pathsToJson(files)}, {"notes", notes}};
}

}  // namespace brdfbake
