// Irradiance as 9 spherical-harmonic coefficients per channel (sh_irradiance.hpp).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_reader.hpp>

#include <brdfbake/env/prefilter_lobe.hpp>

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>

namespace brdfbake {
namespace {
constexpr int kOrder = 2;  // 3 bands
constexpr const char* kFormat = "brdfbake-sh-irradiance";
}  // namespace

std::vector<double> irradianceShScale() { return {1.0, 2.0 / 3.0, 0.25}; }

ShExpansion irradianceSh(const Environment& environment) {
  const Parameterization& map = *environment.map;
  const int n = shCount(kOrder);
  std::vector<std::vector<Rgb>> rows(static_cast<std::size_t>(map.height()), std::vector<Rgb>(n, Rgb::Zero()));
  tbb::parallel_for(0, map.height(), [&](int y) {
    double basis[9];
    std::vector<Rgb>& row = rows[static_cast<std::size_t>(y)];
    for (int x = 0; x < map.width(); ++x) {
      const auto direction = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      const double solidAngle = map.texelSolidAngle(x, y);
      if (!direction || !(solidAngle > 0.0)) continue;
      evaluateShBasis(kOrder, direction->normalized(), basis);
      const Rgb radiance = environment.image.at(x, y).head<3>();
      for (int i = 0; i < n; ++i) row[static_cast<std::size_t>(i)] += (solidAngle * basis[i]) * radiance;
    }
  });
  ShExpansion sh;
  sh.order = kOrder;
  sh.coefficients.assign(n, Rgb::Zero());
  for (const auto& row : rows)
    for (int i = 0; i < n; ++i) sh.coefficients[static_cast<std::size_t>(i)] += row[static_cast<std::size_t>(i)];
  sh.convolve(irradianceShScale());
  return sh;
}

std::vector<double> irradianceShBasisConstants() {
  const double y0 = 0.5 * std::sqrt(1.0 / kPi), y1 = std::sqrt(3.0 / (4.0 * kPi)), y2 = 0.5 * std::sqrt(15.0 / kPi);
  const double y20 = 0.25 * std::sqrt(5.0 / kPi), y22 = 0.25 * std::sqrt(15.0 / kPi);
  return {y0, -y1, y1, -y1, y2, -y2, y20, -y2, y22};
}

std::string irradianceShCmgenText(const ShExpansion& sh) {
  require(sh.order == kOrder && static_cast<int>(sh.coefficients.size()) == shCount(kOrder),
          "cmgen's SH lines hold 3 bands (9 coefficients)");
  const std::vector<double> k = irradianceShBasisConstants();
  std::string text;
  char line[160];
  for (int l = 0; l <= kOrder; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int i = l * (l + 1) + m;
      const Rgb c = sh.coefficients[static_cast<std::size_t>(i)] * k[static_cast<std::size_t>(i)];
      std::snprintf(line, sizeof line, "(%18.15f, %18.15f, %18.15f); // L%d%d, irradiance, pre-scaled base\n", c[0],
                    c[1], c[2], l, m);
      text += line;
    }
  }
  return text;
}

bool isIrradianceShDocument(const nlohmann::json& document) {
  return document.is_object() && document.value("format", "") == kFormat;
}

nlohmann::json irradianceShToJson(const ShExpansion& sh, const nlohmann::json& source) {
  require(sh.order == kOrder && static_cast<int>(sh.coefficients.size()) == shCount(kOrder),
          "irradiance SH files hold 3 bands (9 coefficients)");
  nlohmann::json coefficients = nlohmann::json::array();
  for (const Rgb& c : sh.coefficients) coefficients.push_back({c[0], c[1], c[2]});
  return {
      {"format", kFormat},
      {"version", 1},
      {"bands", kOrder + 1},
      {"quantity", kIrradianceQuantity},
      {"convention",
       "E(n)/pi = sum_i c_i Y_i(n), i = l(l+1)+m: radiance-equivalent irradiance (a constant environment of radiance L "
       "gives L; a Lambertian surface of albedo k_d reflects k_d times it). The coefficients include the cosine-lobe "
       "convolution (A_0 = pi, A_1 = 2pi/3, A_2 = pi/4; Ramamoorthi & Hanrahan 2001, Eq. 8) and the 1/pi; Y_i are "
       "orthonormal (the integral of Y_i Y_j over the sphere is delta_ij), Condon-Shortley phase included."},
      {"basis",
       {"Y_0,0 = 0.282095", "Y_1,-1 = -0.488603 y", "Y_1,0 = 0.488603 z", "Y_1,1 = -0.488603 x",
        "Y_2,-2 = 1.092548 x y", "Y_2,-1 = -1.092548 y z", "Y_2,0 = 0.315392 (3 z^2 - 1)", "Y_2,1 = -1.092548 x z",
        "Y_2,2 = 0.546274 (x^2 - y^2)"}},
      {"frame",
       "(x, y, z) is the unit normal in the environment's frame (y up; a lat-long image's centre looks down -z)"},
      {"coefficients", coefficients},
      {"environment", source}};
}

ShExpansion irradianceShFromJson(const nlohmann::json& document, const std::string& label) {
  if (!isIrradianceShDocument(document)) {
    throw Error(Error::Kind::InvalidInput,
                label + ": format: not an SH irradiance file (expected \"" + kFormat + "\")");
  }
  const auto version = document.find("version");
  if (version == document.end() || !version->is_number_integer() || version->get<int>() != 1) {
    throw Error(Error::Kind::InvalidInput, label + ": version: this brdfbake reads version 1");
  }
  if (const auto quantity = document.find("quantity");
      quantity != document.end() && (!quantity->is_string() || quantity->get<std::string>() != kIrradianceQuantity)) {
    throw Error(Error::Kind::InvalidInput,
                label + ": quantity: this brdfbake reads SH irradiance holding \"" + kIrradianceQuantity + "\"");
  }
  const auto coefficients = document.find("coefficients");
  if (coefficients == document.end() || !coefficients->is_array() || coefficients->size() != 9) {
    throw Error(Error::Kind::InvalidInput, label + ": coefficients: must be an array of 9 [r, g, b] triples (3 bands)");
  }
  ShExpansion sh;
  sh.order = kOrder;
  for (std::size_t i = 0; i < coefficients->size(); ++i) {
    const auto& c = (*coefficients)[i];
    const std::string where = label + ": coefficients[" + std::to_string(i) + "]";
    if (!c.is_array() || c.size() != 3) throw Error(Error::Kind::InvalidInput, where + ": must be [r, g, b]");
    Rgb value;
    for (int k = 0; k < 3; ++k) {
      if (!c[static_cast<std::size_t>(k)].is_number() || !std::isfinite(c[static_cast<std::size_t>(k)].get<double>())) {
        throw Error(Error::Kind::InvalidInput, where + ": must hold finite numbers");
      }
      value[k] = c[static_cast<std::size_t>(k)].get<double>();
    }
    sh.coefficients.push_back(value);
  }
  return sh;
}

void writeIrradianceSh(const ShExpansion& sh, const nlohmann::json& source, const std::filesystem::path& path,
                       const std::vector<std::filesystem::path>& inputs) {
  for (const auto& input : inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  path.string() + ": output would overwrite an input; choose another output path");
    }
  }
  writeFileAtomically(path, irradianceShToJson(sh, source).dump(2) + "\n");
}

std::string_view toString(ShFormat format) { return format == ShFormat::Cmgen ? "cmgen" : "brdfbake"; }

ShFormat parseShFormat(std::string_view name) {
  return parseByName(name, std::array{ShFormat::Brdfbake, ShFormat::Cmgen}, "sh format");
}

std::string ShOutput::problem() const {
  if (file.extension() == (cmgen ? ".txt" : ".json")) return "";
  return cmgen ? "cmgen's SH coefficients are text: give a .txt file"
               : "the SH coefficients are written as JSON (.json)";
}

}  // namespace brdfbake
