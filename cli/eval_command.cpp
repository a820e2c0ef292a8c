// brdfbake eval MODEL: BRDF values of a fit.json, a measured table or a spec material.
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/table_interpolation.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/spec/material_spec.hpp>

#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

struct EvalArgs {
  std::string model;
  std::string wi, wo, pairs;
  std::string format = "auto";
  bool json = false, quiet = false;
};

// A BRDF: channel names and values (1/sr) for (wi, wo) in the local frame.
struct Brdf {
  std::string kind;  // "fit", "table", "merl", "material"
  std::vector<std::string> channels;
  std::function<Eigen::VectorXd(const Vec3& wi, const Vec3& wo)> evaluate;
};

bool startsWithBrace(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Error::Kind::Io, path.string() + ": cannot open");
  char c = 0;
  while (in.get(c)) {
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
  }
  return false;
}

Brdf loadBrdf(const std::string& model, const std::string& formatName) {
  const fs::path path(model);
  if (startsWithBrace(path)) {
    const nlohmann::json document = readJsonFile(path);
    if (isFitFileJson(document)) {
      auto file = std::make_shared<FitFile>(fitFileFromJson(document, model));
      Brdf brdf{"fit", {}, nullptr};
      for (const auto& c : file->fit.model.channels) brdf.channels.push_back(c.name);
      brdf.evaluate = [file](const Vec3& wi, const Vec3& wo) { return file->fit.model.evaluate(wi, wo); };
      return brdf;
    }
    if (document.is_object() && document.contains("maps")) {
      throw Error(Error::Kind::InvalidArgument,
                  model + ": a bake spec; eval takes one material object ({\"model\": ...}), a fit.json or a table");
    }
    // A material names its model with a string; a fit.json has "channels" and a "model" object.
    const bool namesAModel = document.is_object() && document.contains("model") && document["model"].is_string();
    if (document.is_object() && !namesAModel) {
      throw Error(Error::Kind::InvalidInput,
                  model + (document.contains("channels")
                               ? ": looks like a fit.json but has no \"format\": \"" + std::string(kFitFileFormat) +
                                     "\" (files written by brdfbake fit have it)"
                               : ": neither a material (\"model\": \"phong\", ...) nor a fit.json (\"format\": \"" +
                                     std::string(kFitFileFormat) + "\")"));
    }
    std::shared_ptr<const Material> material;
    try {
      material = parseMaterial(document, "", {path.parent_path().empty() ? fs::path(".") : path.parent_path()});
    } catch (const Error& e) {
      throw Error(e.kind(), model + ": " + e.what());
    }
    if (!material->usesLights()) {
      throw Error(
          Error::Kind::InvalidArgument,
          model + ": this " + std::string(material->model()) +
              " material ignores lights (a reflectance map), so it has no BRDF to evaluate; use its lighting mode");
    }
    // The BRDF a material implies: shade(n, v, l) / (n.l), n = z.
    return {"material", {"R", "G", "B"}, [material](const Vec3& wi, const Vec3& wo) -> Eigen::VectorXd {
              if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return Eigen::VectorXd::Zero(3);
              const Vec3 n = Vec3::UnitZ();
              const Rgb value = material->shade({n, wo, reflect(wo, n)}, wi) / wi.z();
              return value.matrix();
            }};
  }
  const TableFormat format = parseTableFormat(formatName);
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

void checkValues(const Eigen::VectorXd& values, const std::string& where) {
  if (!values.allFinite()) throw Error(Error::Kind::Numerical, where + ": the model gave a non-finite value");
}

std::string formatValues(const Eigen::VectorXd& values) {
  std::ostringstream out;
  out.precision(9);
  for (Eigen::Index i = 0; i < values.size(); ++i) out << (i ? " " : "") << values[i];
  return out.str();
}

nlohmann::json jsonValues(const Eigen::VectorXd& values) {
  nlohmann::json array = nlohmann::json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) array.push_back(values[i]);
  return array;
}

int runEval(const EvalArgs& args) {
  const bool single = !args.wi.empty() || !args.wo.empty();
  if (single == !args.pairs.empty()) {
    throw Error(Error::Kind::InvalidArgument, "give either --wi and --wo, or --pairs FILE");
  }
  if (single && (args.wi.empty() || args.wo.empty()))
    throw Error(Error::Kind::InvalidArgument, "--wi and --wo go together");
  Vec3 wi, wo;
  if (single) {
    wi = parseVector(args.wi, "--wi");
    wo = parseVector(args.wo, "--wo");
    if (!(wi.norm() > 0.0) || !(wo.norm() > 0.0))
      throw Error(Error::Kind::InvalidArgument, "--wi and --wo must be non-zero");
  }
  std::ifstream pairs;
  if (!single) {
    pairs.open(args.pairs);
    if (!pairs) throw Error(Error::Kind::Io, args.pairs + ": cannot open");
  }
  const Brdf brdf = loadBrdf(args.model, args.format);
  // More than R, G, B (a spectral table or fit): the columns are named once, on stderr, so the
  // values on stdout stay one line per direction for scripts.
  if (!args.json && !args.quiet && brdf.channels.size() > 3) {
    std::cerr << "columns (" << brdf.channels.size() << " channels):";
    for (const auto& name : brdf.channels) std::cerr << " " << name;
    std::cerr << "\n";
  }

  if (single) {
    const Eigen::VectorXd value = brdf.evaluate(wi.normalized(), wo.normalized());
    checkValues(value, args.model);
    if (args.json) {
      std::cout << nlohmann::json{{"model", args.model},
                                  {"kind", brdf.kind},
                                  {"channels", brdf.channels},
                                  {"wi", {wi.x(), wi.y(), wi.z()}},
                                  {"wo", {wo.x(), wo.y(), wo.z()}},
                                  {"value", jsonValues(value)}}
                       .dump()
                << "\n";
    } else {
      std::cout << formatValues(value) << "\n";
    }
    return 0;
  }

  // --pairs: every line is read and checked before anything is printed.
  std::vector<std::string> lines;
  std::vector<std::optional<Eigen::VectorXd>> results;
  std::string line;
  int number = 0;
  while (std::getline(pairs, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') {  // blank and comment lines are echoed
      lines.push_back(line);
      results.emplace_back();
      continue;
    }
    std::istringstream fields(line);
    double a[4];
    std::string extra;
    int read = 0;
    for (; read < 4; ++read) {
      std::string field;
      if (!(fields >> field)) break;
      try {
        std::size_t used = 0;
        a[read] = std::stod(field, &used);
        if (used != field.size() || !std::isfinite(a[read])) throw std::invalid_argument(field);
      } catch (const std::exception&) {
        throw Error::atFile(Error::Kind::InvalidInput, args.pairs, number,
                            "'" + field + "' is not a finite number (expected theta_i phi_i theta_s phi_s in radians)");
      }
    }
    if (read != 4 || (fields >> extra)) {
      throw Error::atFile(Error::Kind::InvalidInput, args.pairs, number,
                          "expected 4 numbers theta_i phi_i theta_s phi_s (radians), got '" + line + "'");
    }
    if (a[0] < 0.0 || a[0] > kPi || a[2] < 0.0 || a[2] > kPi) {
      throw Error::atFile(Error::Kind::InvalidInput, args.pairs, number, "theta must lie in [0, pi] radians");
    }
    const Eigen::VectorXd value = brdf.evaluate(directionFromAngles(a[0], a[1]), directionFromAngles(a[2], a[3]));
    checkValues(value, args.pairs + ":" + std::to_string(number));
    lines.push_back(line);
    results.emplace_back(value);
  }
  if (args.json) {
    nlohmann::json values = nlohmann::json::array();
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (results[i]) values.push_back({{"line", i + 1}, {"value", jsonValues(*results[i])}});
    }
    std::cout << nlohmann::json{{"model", args.model},
                                {"kind", brdf.kind},
                                {"channels", brdf.channels},
                                {"pairs", args.pairs},
                                {"values", values}}
                     .dump()
              << "\n";
  } else {
    for (std::size_t i = 0; i < results.size(); ++i)
      std::cout << (results[i] ? formatValues(*results[i]) : lines[i]) << "\n";
  }
  return 0;
}

}  // namespace

Command addEvalCommand(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* command =
      app.add_subcommand("eval", "Evaluate a BRDF (fit.json, measured table or spec material) at given directions");
  command->footer(R"(Directions are in the local frame, z along the normal, both pointing away from the surface:
wi towards the light, wo towards the viewer. Prints one BRDF value (1/sr) per channel; 0 when a
direction is at or below the horizon.

MODEL is
  - a fit.json from `brdfbake fit` (the fitted lobes, channels as fitted);
  - a measured table (.astm, .brdf, .mat: nearest incident angle, then inverse-distance weighting
    over the 4 nearest measured outgoing directions, using the mirror symmetry; .binary MERL: the
    nearest bin, 0 where unmeasured);
  - a JSON file holding one material object, e.g. {"model": "phong", "exponent": 50}: the BRDF it
    implies, shade / (n.l) (materials that ignore lights have none).

--pairs FILE reads lines "theta_i phi_i theta_s phi_s" (radians, Cornell convention: theta from the
normal, phi from x towards y) and prints one line per input line (blank and # lines echoed).

Examples:
  brdfbake eval fit.json --wi 0.5,0,0.866 --wo -0.5,0,0.866
  brdfbake eval ../shared/data/cornell/garnet_red.astm --wi 0.5,0,0.866 --wo -0.5,0,0.866 --json
  printf '0.5236 0 0.5236 3.1416\n' > pairs.txt && brdfbake eval fit.json --pairs pairs.txt)");
  command->add_option("model", args->model, "fit.json, measured table, or material JSON")->required();
  auto* wi = command->add_option("--wi", args->wi, "Light direction X,Y,Z (local frame)");
  auto* wo = command->add_option("--wo", args->wo, "View direction X,Y,Z (local frame)");
  auto* pairs = command->add_option("--pairs", args->pairs, "File of 'theta_i phi_i theta_s phi_s' lines (radians)");
  pairs->excludes(wi)->excludes(wo);
  command->add_option("--format", args->format, "Table format when MODEL is a table")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "astm", "pbrt", "merl", "mat"}));
  addJsonFlag(command, args->json, "the model, its channels, the directions and the values");
  addQuietFlag(command, args->quiet);
  return [args] { return runEval(*args); };
}

}  // namespace brdfbake::cli
