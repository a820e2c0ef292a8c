#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/evaluate.hpp>

#include <sstream>

namespace brdfbake {

namespace {

void checkValues(const Eigen::VectorXd& values, const std::string& where) {
  if (!values.allFinite()) throw Error(Error::Kind::Numerical, where + ": the model gave a non-finite value");
}

nlohmann::json valuesJson(const Eigen::VectorXd& values) {
  nlohmann::json array = nlohmann::json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) array.push_back(values[i]);
  return array;
}

// One line of a pairs file: four finite angles (radians), or nullopt for a blank or comment line.
std::optional<std::array<double, 4>> parsePairLine(const std::string& line, const std::string& file, int number) {
  const auto first = line.find_first_not_of(" \t");
  if (first == std::string::npos || line[first] == '#') return std::nullopt;
  std::istringstream fields(line);
  std::array<double, 4> a{};
  int read = 0;
  for (std::string field; read < 4 && fields >> field; ++read) {
    const std::optional<double> value = finiteNumberIn(field);
    if (!value) {
      throw Error::atFile(Error::Kind::InvalidInput, file, number,
                          "'" + shortenForMessage(field, 40) +
                              "' is not a finite number (expected theta_i phi_i theta_s phi_s in radians)");
    }
    a[read] = *value;
  }
  std::string extra;
  if (read != 4 || (fields >> extra)) {
    throw Error::atFile(
        Error::Kind::InvalidInput, file, number,
        "expected 4 numbers theta_i phi_i theta_s phi_s (radians), got '" + shortenForMessage(line, 80) + "'");
  }
  if (a[0] < 0.0 || a[0] > kPi || a[2] < 0.0 || a[2] > kPi) {
    throw Error::atFile(Error::Kind::InvalidInput, file, number, "theta must lie in [0, pi] radians");
  }
  return a;
}

void evaluatePairsFile(const EvaluateOptions& options, const BrdfFile& brdf, EvaluateResult& result) {
  std::istringstream in(readTextFile(options.pairs, "pairs file"));
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    EvaluateResult::Row row{number, Vec3::Zero(), Vec3::Zero(), std::nullopt, line};
    if (const auto a = parsePairLine(line, options.pairs.string(), number)) {
      row.wi = directionFromAngles((*a)[0], (*a)[1]);
      row.wo = directionFromAngles((*a)[2], (*a)[3]);
      row.value = brdf.evaluate(row.wi, row.wo);
      checkValues(*row.value, options.pairs.string() + ":" + std::to_string(number));
    }
    result.rows.push_back(std::move(row));
  }
}

}  // namespace

void EvaluateOptions::validate() const {
  const bool single = wi || wo;
  require(single != !pairs.empty(), "give either wi and wo, or a pairs file");
  require(!single || (wi && wo), "wi and wo go together");
  if (single)
    require(wi->allFinite() && wo->allFinite() && wi->norm() > 0.0 && wo->norm() > 0.0,
            "wi and wo must be finite and non-zero");
}

EvaluateResult evaluateBrdf(const EvaluateOptions& options, const Context& context) {
  context.checkCancelled();
  options.validate();
  if (!options.pairs.empty()) requireInputFile(options.pairs, "pairs file");
  const BrdfFile brdf = loadBrdf(options.model, options.format);
  EvaluateResult result;
  result.model = options.model;
  result.pairs = options.pairs;
  result.kind = brdf.kind;
  result.channels = brdf.channels;
  if (!options.pairs.empty()) {
    evaluatePairsFile(options, brdf, result);
    return result;
  }
  EvaluateResult::Row row{0, options.wi->normalized(), options.wo->normalized(), std::nullopt, ""};
  row.value = brdf.evaluate(row.wi, row.wo);
  checkValues(*row.value, options.model.string());
  result.rows.push_back(std::move(row));
  return result;
}

std::string EvaluateResult::briefReport() const {
  std::ostringstream out;
  out.precision(9);
  for (const auto& row : rows) {
    if (!row.value) {
      out << row.text << "\n";
      continue;
    }
    for (Eigen::Index i = 0; i < row.value->size(); ++i) out << (i ? " " : "") << (*row.value)[i];
    out << "\n";
  }
  return out.str();
}

std::string EvaluateResult::columnsLine() const {
  if (channels.size() <= 3) return "";
  std::string names;
  for (const auto& name : channels) names += " " + name;
  return "columns (" + std::to_string(channels.size()) + " channels):" + names + "\n";
}

nlohmann::json EvaluateResult::toJson() const {
  nlohmann::json report = {{"model", model.string()}, {"kind", kind}, {"channels", channels}};
  if (pairs.empty()) {
    const Row& row = rows.front();
    report["wi"] = {row.wi.x(), row.wi.y(), row.wi.z()};
    report["wo"] = {row.wo.x(), row.wo.y(), row.wo.z()};
    report["value"] = valuesJson(*row.value);
    return report;
  }
  report["pairs"] = pairs.string();
  report["values"] = nlohmann::json::array();
  for (const auto& row : rows) {
    if (row.value) report["values"].push_back({{"line", row.line}, {"value", valuesJson(*row.value)}});
  }
  return report;
}

}  // namespace brdfbake
