#include <brdfbake/io/image_io.hpp>
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/run/describe_output.hpp>

#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

// A plain image (no brdfbake metadata), or nullopt for anything brdfbake wrote.
std::optional<Image> plainImage(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec) || path.extension() == ".json") return std::nullopt;
  Image image = readImage(path);
  if (!image.metadata.empty()) return std::nullopt;
  return image;
}

nlohmann::json describeBrdfbakeOutput(const BakedOutput& output) {
  nlohmann::json info = output.describe();
  const nlohmann::json& metadata = output.metadata();
  switch (output.kind()) {
    case OutputKind::RadialProfile:
    case OutputKind::FresnelTable:
      info["parameterization"] = metadataValue(metadata, "parameterization", std::string());
      info["width"] = info["resolution"];
      info["height"] = 1;
      break;
    case OutputKind::ShIrradiance:
      info["parameterization"] = "sh";
      info.erase("channels");
      break;
    default:
      break;
  }
  info["convention_version"] = metadataValue(metadata, "convention_version", 0);
  info["spec"] = output.kind() == OutputKind::ShIrradiance
                     ? metadataValue(metadata, "environment", nlohmann::json::object())
                     : metadataValue(metadata, "spec", nlohmann::json::object());
  if (output.kind() == OutputKind::ShIrradiance) info["coefficients"] = metadata["coefficients"];
  return info;
}

}  // namespace

OutputDescription describeOutput(const fs::path& path) {
  OutputDescription result;
  result.path = path;
  result.description = {{"file", path.string()}, {"channels", "RGBA"}};
  if (const auto plain = plainImage(path)) {
    result.description.update(
        {{"brdfbake", false}, {"kind", "plain image"}, {"width", plain->width()}, {"height", plain->height()}});
    return result;
  }
  result.description["brdfbake"] = true;
  result.description.update(describeBrdfbakeOutput(BakedOutput::open(path)));
  return result;
}

std::string OutputDescription::briefReport() const {
  const nlohmann::json& info = description;
  std::ostringstream out;
  out << path.string() << ": " << info["kind"].get<std::string>();
  if (info.contains("width")) out << ", " << info["width"] << " x " << info["height"] << " RGBA";
  out << "\n";
  if (!info["brdfbake"].get<bool>()) return out.str() + "  no brdfbake metadata (a plain image)\n";
  if (info.contains("parameterization")) {
    out << "  parameterization: " << info["parameterization"].get<std::string>();
    if (info.contains("resolution")) out << ", resolution " << info["resolution"];
    if (info["parameterization"] != "sh") out << " (convention v" << info["convention_version"] << ")";
    out << "\n";
  }
  if (info.contains("axis")) out << "  axis: " << info["axis"].dump() << "\n";
  if (info.contains("slices")) {
    out << "  " << info["slices"] << " slices over n.v from " << info["min_cos"] << " to " << info["max_cos"] << "\n";
  }
  if (info.contains("files") && info["files"].size() > 1) {
    out << "  files: " << info["files"].front().get<std::string>() << " ... " << info["files"].back().get<std::string>()
        << " (" << info["files"].size() << ")\n";
  }
  out << "  lookup: " << info["lookup"].get<std::string>() << "\n";
  if (info.contains("coefficients")) {
    out << "  coefficients: " << info["coefficients"].dump() << "\n";
  } else {
    out << "  spec: " << info["spec"].dump() << "\n";
  }
  return out.str();
}

}  // namespace brdfbake
