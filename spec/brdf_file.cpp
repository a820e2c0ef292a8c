#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/table_interpolation.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/spec/brdf_file.hpp>
#include <brdfbake/spec/material_spec.hpp>

#include <fstream>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

bool startsWithBrace(const fs::path& path) {
  requireInputFile(path, "BRDF file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Error::Kind::Io, shortenForMessage(path.string()) + ": cannot open");
  for (char c = 0; in.get(c);) {
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
  }
  return false;
}

BrdfFile fitBrdf(const nlohmann::json& document, const fs::path& path) {
  auto file = std::make_shared<FitFile>(fitFileFromJson(document, path.string()));
  BrdfFile brdf{"fit", {}, nullptr};
  for (const auto& c : file->fit.model.channels) brdf.channels.push_back(c.name);
  brdf.evaluate = [file](const Vec3& wi, const Vec3& wo) { return file->fit.model.evaluate(wi, wo); };
  return brdf;
}

BrdfFile materialBrdf(const nlohmann::json& document, const fs::path& path) {
  const std::string name = shortenForMessage(path.string());
  if (document.is_object() && document.contains("maps")) {
    throw Error(
        Error::Kind::InvalidInput,
        name + ": a bake spec; a BRDF file holds one material object ({\"model\": ...}), a fit.json or a table");
  }
  // A material names its model with a string; a fit.json has "channels" and a "model" object.
  const bool namesAModel = document.is_object() && document.contains("model") && document["model"].is_string();
  if (!namesAModel) {
    throw Error(Error::Kind::InvalidInput,
                name + (document.is_object() && document.contains("channels")
                            ? ": looks like a fit.json but has no \"format\": \"" + std::string(kFitFileFormat) +
                                  "\" (files written by brdfbake fit have it)"
                            : ": neither a material (\"model\": \"phong\", ...) nor a fit.json (\"format\": \"" +
                                  std::string(kFitFileFormat) + "\")"));
  }
  std::shared_ptr<const Material> material;
  try {
    material = parseMaterial(document, "", {path.parent_path().empty() ? fs::path(".") : path.parent_path()});
  } catch (const Error& e) {
    throw Error(e.kind(), name + ": " + e.what());
  }
  if (!material->usesLights()) {
    throw Error(Error::Kind::InvalidArgument, name + ": this " + std::string(material->model()) +
                                                  " material ignores lights (a reflectance map), so it has no BRDF; "
                                                  "use its lighting mode");
  }
  // The BRDF a material implies: shade(n, v, l) / (n.l), n = z.
  return {"material", {"R", "G", "B"}, [material](const Vec3& wi, const Vec3& wo) -> Eigen::VectorXd {
            if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return Eigen::VectorXd::Zero(3);
            const Vec3 n = Vec3::UnitZ();
            const Rgb value = material->shade({n, wo, reflect(wo, n)}, wi) / wi.z();
            return value.matrix();
          }};
}

BrdfFile tableBrdf(const fs::path& path, TableFormat format) {
  const TableFormat detected = format == TableFormat::Auto ? detectTableFormat(path) : format;
  if (detected == TableFormat::Merl) {
    auto merl = std::make_shared<MerlTable>(readMerl(path));
    // Unmeasured bins and directions below the horizon give 0.
    return {"merl", {"R", "G", "B"}, [merl](const Vec3& wi, const Vec3& wo) -> Eigen::VectorXd {
              const auto value = merl->evaluate(wi, wo);
              return value ? Eigen::VectorXd(value->matrix()) : Eigen::VectorXd::Zero(3);
            }};
  }
  auto table = std::make_shared<TableInterpolator>(readMeasuredTable(path, detected));
  return {"table", table->table().channelNames,
          [table](const Vec3& wi, const Vec3& wo) { return table->evaluate(wi, wo); }};
}

}  // namespace

BrdfFile loadBrdf(const fs::path& file, TableFormat format) {
  if (!startsWithBrace(file)) return tableBrdf(file, format);
  const nlohmann::json document = readJsonFile(file);
  return isFitFileJson(document) ? fitBrdf(document, file) : materialBrdf(document, file);
}

}  // namespace brdfbake
