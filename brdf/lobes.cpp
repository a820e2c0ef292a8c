#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>

#include <algorithm>
#include <array>

namespace brdfbake {

std::string_view toString(LobeElevation elevation) {
  return elevation == LobeElevation::Constant ? "constant" : "varying";
}

LobeElevation parseLobeElevation(std::string_view name) {
  return parseByName(name, std::array{LobeElevation::Constant, LobeElevation::Varying}, "elevation");
}

std::string_view toString(ColorProfile profile) { return profile == ColorProfile::None ? "none" : "difference_angle"; }

ColorProfile parseColorProfile(std::string_view name) {
  return parseByName(name, std::array{ColorProfile::None, ColorProfile::DifferenceAngle}, "colour profile");
}

std::string_view toString(LobeMaterialMode mode) {
  switch (mode) {
    case LobeMaterialMode::Reflectance:
      return "reflectance";
    case LobeMaterialMode::Lighting:
      return "lighting";
    case LobeMaterialMode::Prefiltered:
      return "prefiltered";
  }
  return "reflectance";
}

LobeMaterialMode parseLobeMaterialMode(std::string_view name) {
  return parseByName(
      name, std::array{LobeMaterialMode::Reflectance, LobeMaterialMode::Lighting, LobeMaterialMode::Prefiltered},
      "mode");
}

namespace {
// A colour profile is kColorProfileCount finite coefficients >= 0 where the model has profiles
// and the term has a weight, empty elsewhere.
void validateColorProfile(const std::vector<double>& profile, bool expected, const std::string& at) {
  if (!expected) {
    require(profile.empty(), at + ": a colour profile where the model has none (or for C_F of a lobe without one)");
    return;
  }
  require(profile.size() == static_cast<std::size_t>(kColorProfileCount),
          at + ": a colour profile holds " + std::to_string(kColorProfileCount) + " coefficients");
  for (double p : profile)
    require(std::isfinite(p) && p >= 0.0 && p <= kMaxLobeWeight,
            at + ": colour profiles must be finite and in [0, 1e6]");
}

// Every channel's table coefficients match the model's table: coefficientCount finite numbers
// within kMaxTableLogValue, or none without a table.
void validateTable(const LobeModel& model) {
  model.halfDifference.validate();
  if (model.hasHalfDifference()) {
    require(model.elevation == LobeElevation::Constant && model.colorProfile == ColorProfile::None,
            "lobe model: a half-difference table has constant elevation and no colour profile");
    for (const auto& channel : model.channels)
      require(channel.lobes.empty() && channel.diffuse == 0.0,
              "lobe model: channel '" + channel.name + "': a half-difference table has no diffuse term and no lobes");
  }
  const auto count = static_cast<std::size_t>(model.hasHalfDifference() ? model.halfDifference.coefficientCount() : 0);
  for (const auto& channel : model.channels) {
    const std::string where = "lobe model: channel '" + channel.name + "' table";
    require(channel.halfDifferenceCoefficients.size() == count,
            where + ": " + std::to_string(count) + " coefficient(s) expected (the model's table), got " +
                std::to_string(channel.halfDifferenceCoefficients.size()));
    for (double a : channel.halfDifferenceCoefficients)
      require(
          std::isfinite(a) && std::abs(a) <= kMaxTableLogValue,
          where + ": coefficients must be finite with |a| <= " + std::to_string(static_cast<int>(kMaxTableLogValue)));
  }
}

void validateColorProfiles(const LobeModel& model) {
  const bool profiled = model.colorProfile != ColorProfile::None;
  for (const auto& channel : model.channels) {
    const std::string where = "lobe model: channel '" + channel.name + "'";
    validateColorProfile(channel.diffuseProfile, profiled, where + " diffuse");
    for (std::size_t k = 0; k < channel.lobes.size(); ++k) {
      const Lobe& lobe = channel.lobes[k];
      const std::string at = where + " lobe " + std::to_string(k);
      validateColorProfile(lobe.weightProfile, profiled, at + " weight");
      validateColorProfile(lobe.fresnelProfile, profiled && lobe.halfVector, at + " fresnel");
    }
  }
}
}  // namespace

void LobeModel::validate() const {
  require(!channels.empty(), "lobe model: no channels");
  require(std::isfinite(minCos) && std::isfinite(maxCos) && 0.0 < minCos && minCos <= maxCos && maxCos <= 1.0,
          "lobe model: elevation range must satisfy 0 < minCos <= maxCos <= 1");
  const std::size_t count = static_cast<std::size_t>(elevationCoefficientCount(elevation));
  for (const auto& channel : channels) {
    const std::string where = "lobe model: channel '" + channel.name + "'";
    require(channel.lobes.size() <= static_cast<std::size_t>(kMaxModelLobes),
            where + ": at most " + std::to_string(kMaxModelLobes) + " lobes");
    require(std::isfinite(channel.diffuse) && channel.diffuse >= 0.0 && channel.diffuse <= kMaxLobeWeight,
            where + ": diffuse must be finite and in [0, 1e6]");
    for (std::size_t k = 0; k < channel.lobes.size(); ++k) {
      const Lobe& lobe = channel.lobes[k];
      const std::string at = where + " lobe " + std::to_string(k);
      require(lobe.weight.size() == count && lobe.exponent.size() == count,
              at + ": " + std::string(toString(elevation)) + " lobes need " + std::to_string(count) +
                  " coefficient(s) per parameter");
      for (double c : lobe.weight) {
        require(std::isfinite(c) && c >= 0.0 && c <= kMaxLobeWeight, at + ": weights must be finite and in [0, 1e6]");
        require(count == 1 || c > 0.0, at + ": varying weights must be > 0 (they are interpolated geometrically)");
      }
      for (double n : lobe.exponent) {
        require(std::isfinite(n) && n >= kMinLobeExponent && n <= kMaxLobeExponent,
                at + ": exponents must lie in [1, 1e5]");
      }
      require(std::isfinite(lobe.cxy) && std::abs(lobe.cxy) <= kMaxLobeCxy,
              at + ": cxy must be finite with |cxy| <= " + std::to_string(static_cast<int>(kMaxLobeCxy)));
      require(std::isfinite(lobe.fresnel) && lobe.fresnel >= 0.0 && lobe.fresnel <= kMaxLobeWeight,
              at + ": fresnel must be finite and in [0, 1e6]");
      require(lobe.halfVector || lobe.fresnel == 0.0, at + ": fresnel applies to half-vector lobes only");
      require(!lobe.halfVector || lobe.cxy == -1.0, at + ": a half-vector lobe has no cxy");
      for (double n : lobe.exponent) {
        require(n * std::log(std::max(1.0, std::abs(lobe.cxy))) <= kMaxLobeGrowthLog,
                at + ": exponent * ln|cxy| must be <= " + std::to_string(static_cast<int>(kMaxLobeGrowthLog)) +
                    " (the lobe's growth |a|^n would overflow)");
      }
    }
  }
  validateColorProfiles(*this);
  validateTable(*this);
  if (!wavelengthsNm.empty()) {
    require(wavelengthsNm.size() == channels.size(), "lobe model: one wavelength per channel");
    for (std::size_t i = 0; i < wavelengthsNm.size(); ++i) {
      require(std::isfinite(wavelengthsNm[i]) && (i == 0 || wavelengthsNm[i] > wavelengthsNm[i - 1]),
              "lobe model: wavelengths must be finite and strictly increasing");
    }
  }
}

double LobeModel::elevationCoordinate(double u) const {
  const double range = std::log(maxCos / minCos);
  if (!(range > 1e-12) || !(u > minCos)) return 0.0;
  return clampFinite(std::log(u / minCos) / range, 0.0, 1.0);
}

double LobeModel::weight(std::size_t channel, std::size_t lobe, double u) const {
  const Lobe& l = channels.at(channel).lobes.at(lobe);
  return elevationBlend(l.weight.data(), static_cast<int>(l.weight.size()), elevationCoordinate(u)) *
         colorProfileFactor(l.weightProfile, LobeGeometry::mirrorDifferenceCoordinate(u));
}

double LobeModel::fresnel(std::size_t channel, std::size_t lobe, double u) const {
  const Lobe& l = channels.at(channel).lobes.at(lobe);
  return l.fresnel * colorProfileFactor(l.fresnelProfile, LobeGeometry::mirrorDifferenceCoordinate(u));
}

double LobeModel::exponent(std::size_t channel, std::size_t lobe, double u) const {
  const Lobe& l = channels.at(channel).lobes.at(lobe);
  return elevationBlend(l.exponent.data(), static_cast<int>(l.exponent.size()), elevationCoordinate(u));
}

LobeModel LobeModel::atElevation(double u) const {
  if (elevation == LobeElevation::Constant) return *this;
  const double t = elevationCoordinate(u);
  auto frozen = [t](const std::vector<double>& values) {
    if (std::all_of(values.begin(), values.end(), [&](double v) { return v == values.front(); })) return values.front();
    return elevationBlend(values.data(), static_cast<int>(values.size()), t);
  };
  LobeModel result = *this;
  result.elevation = LobeElevation::Constant;
  for (auto& channel : result.channels)
    for (auto& lobe : channel.lobes) {
      lobe.weight = {frozen(lobe.weight)};
      lobe.exponent = {frozen(lobe.exponent)};
    }
  return result;
}

LobeModel LobeModel::prefilterFormAt(double u) const {
  LobeModel result = atElevation(u);
  if (colorProfile == ColorProfile::None) return result;
  const double s = LobeGeometry::mirrorDifferenceCoordinate(u);
  auto factor = [s](std::vector<double>& profile) {
    const double f = colorProfileFactor(profile, s);
    profile.clear();
    return f;
  };
  result.colorProfile = ColorProfile::None;
  for (auto& channel : result.channels) {
    channel.diffuse *= factor(channel.diffuseProfile);
    for (auto& lobe : channel.lobes) {
      lobe.weight[0] *= factor(lobe.weightProfile);
      lobe.fresnel *= factor(lobe.fresnelProfile);
    }
  }
  return result;
}

namespace {
// What every channel's value at one pair of directions shares: the geometry, the Bernstein weights at
// the elevation coordinate and at theta_d's (computed once for all channels: each is a few pow calls,
// and a spectral model has 31 channels of up to a dozen blends and profiles each).
struct PointTerms {
  LobeGeometry geometry;
  int count = 1;                              // elevationCoefficientCount
  double elevation[kVaryingDegree + 1] = {};  // Bernstein weights at the elevation coordinate
  // Bernstein weights at theta_d / 90 degrees (those at 0, unused, without profiles).
  double profile[kColorProfileCount] = {1.0};
  HalfDifferenceBasis table;  // the table's basis at theta_h and theta_d (unused without a table)
};

PointTerms pointTerms(const LobeModel& model, double u, const LobeGeometry& geometry) {
  PointTerms p;
  p.geometry = geometry;
  p.count = elevationCoefficientCount(model.elevation);
  if (p.count > 1) bernsteinWeights(p.count, model.elevationCoordinate(u), p.elevation);
  if (model.colorProfile != ColorProfile::None)
    bernsteinWeights(kColorProfileCount, std::clamp(geometry.differenceCoordinate(), 0.0, 1.0), p.profile);
  if (model.hasHalfDifference()) p.table = halfDifferenceBasis(model.halfDifference, geometry);
  return p;
}

// The geometry of the light on the view's mirror direction at view cosine u: l_x v_x + l_y v_y =
// -(1 - u^2), l_z v_z = u^2 (r_v . l = 1), l + v = 2 u n, h = n.
LobeGeometry mirrorGeometry(double u) { return {-(1.0 - u * u), u * u, u, u, 4.0 * u * u}; }

// One lobe's value at one point per unit weight, and a half-vector lobe's per unit C_F (0 for others):
// the model is linear in the weights.
struct UnitLobe {  // no initialisers: channelValues keeps an array of them on the stack per point
  double perWeight;
  double perFresnel;
};

UnitLobe unitLobe(const Lobe& lobe, const PointTerms& p) {
  const double exponent = elevationBlendWith(lobe.exponent.data(), p.count, p.elevation);
  if (lobe.halfVector) {  // (C + C_F (1 - l.h)^5) D / (4 n.l n.v): C_F's value is C's times (1 - l.h)^5
    const double perWeight = halfVectorLobe(1.0, 0.0, exponent, p.geometry);
    return {perWeight, perWeight * p.geometry.schlick()};
  }
  return {normalizedLobe(1.0, exponent, p.geometry.cosine(lobe.cxy)), 0.0};
}

// One channel of the model (see brdf/lobes.hpp) at one point: the diffuse term and every lobe at the
// elevation coordinate, each weight times its colour profile at theta_d, the lobes' values per unit
// weight from `unit(k, lobe)` (no allocation: this runs per sample and channel).
template <class UnitLobes>
double channelBrdf(const LobeChannel& channel, const PointTerms& p, const UnitLobes& unit) {
  double value = diffuseTerm(channel.diffuse * colorProfileFactorWith(channel.diffuseProfile, p.profile));
  for (std::size_t k = 0; k < channel.lobes.size(); ++k) {
    const Lobe& lobe = channel.lobes[k];
    const UnitLobe perUnit = unit(k, lobe);
    value += elevationBlendWith(lobe.weight.data(), p.count, p.elevation) *
             colorProfileFactorWith(lobe.weightProfile, p.profile) * perUnit.perWeight;
    if (lobe.halfVector)
      value += lobe.fresnel * colorProfileFactorWith(lobe.fresnelProfile, p.profile) * perUnit.perFresnel;
  }
  if (!channel.halfDifferenceCoefficients.empty())
    value += std::exp(p.table.logValue(channel.halfDifferenceCoefficients));
  return value;
}

double channelBrdf(const LobeChannel& channel, const PointTerms& p) {
  return channelBrdf(channel, p, [&p](std::size_t, const Lobe& lobe) { return unitLobe(lobe, p); });
}

// Whether every channel has channel 0's lobe shapes (axis, c_xy and exponents, to the bit), as a
// shared-shape fit writes them: then a lobe's value per unit weight is the same in every channel.
bool sharesShapes(const LobeModel& model) {
  if (model.channels.empty()) return false;
  const std::vector<Lobe>& first = model.channels.front().lobes;
  if (first.size() > static_cast<std::size_t>(kMaxModelLobes)) return false;
  for (const auto& channel : model.channels) {
    if (channel.lobes.size() != first.size()) return false;
    for (std::size_t k = 0; k < first.size(); ++k) {
      const Lobe& a = channel.lobes[k];
      if (a.halfVector != first[k].halfVector || a.cxy != first[k].cxy || a.exponent != first[k].exponent) return false;
    }
  }
  return true;
}

// Every channel's value at one point. With shared shapes (sharesShapes(model)) each lobe's power is
// taken once for all channels (a 31-wavelength shared fit's value costs the powers of one channel, not 31).
Eigen::VectorXd channelValues(const LobeModel& model, bool sharedShapes, const PointTerms& p) {
  Eigen::VectorXd values(static_cast<Eigen::Index>(model.channels.size()));
  if (!sharedShapes) {
    for (std::size_t c = 0; c < model.channels.size(); ++c)
      values[static_cast<Eigen::Index>(c)] = channelBrdf(model.channels[c], p);
    return values;
  }
  std::array<UnitLobe, kMaxModelLobes> units;  // the first lobes.size() set below
  const std::vector<Lobe>& lobes = model.channels.front().lobes;
  for (std::size_t k = 0; k < lobes.size(); ++k) units[k] = unitLobe(lobes[k], p);
  const auto shared = [&units](std::size_t k, const Lobe&) { return units[k]; };
  for (std::size_t c = 0; c < model.channels.size(); ++c)
    values[static_cast<Eigen::Index>(c)] = channelBrdf(model.channels[c], p, shared);
  return values;
}
}  // namespace

double LobeModel::evaluate(std::size_t channel, const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return 0.0;
  return channelBrdf(channels.at(channel), pointTerms(*this, wo.z(), LobeGeometry::local(wi, wo)));
}

Eigen::VectorXd LobeModel::evaluate(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return Eigen::VectorXd::Zero(static_cast<Eigen::Index>(channels.size()));
  return channelValues(*this, sharesShapes(*this), pointTerms(*this, wo.z(), LobeGeometry::local(wi, wo)));
}

double LobeModel::mirrorValue(std::size_t channel, double u) const {
  return channelBrdf(channels.at(channel), pointTerms(*this, u, mirrorGeometry(u)));
}

bool LobeModel::allAboutMirror() const {
  if (hasHalfDifference()) return false;
  for (const auto& channel : channels)
    for (const auto& lobe : channel.lobes)
      if (!lobe.aboutMirror()) return false;
  return true;
}

Eigen::Matrix<double, 3, Eigen::Dynamic> LobeModel::rgbWeights() const {
  const auto n = static_cast<Eigen::Index>(channels.size());
  if (!wavelengthsNm.empty()) return SpectrumToRgb(wavelengthsNm).srgbWeights();
  if (n == 1) return Eigen::Matrix<double, 3, Eigen::Dynamic>::Ones(3, 1);
  if (n == 3 && channels[0].name == "R" && channels[1].name == "G" && channels[2].name == "B") {
    return Eigen::Matrix<double, 3, Eigen::Dynamic>::Identity(3, 3);
  }
  throw Error(Error::Kind::InvalidArgument,
              "lobe model: cannot make RGB from " + std::to_string(n) +
                  " channels (need R, G, B, one channel, or wavelengths for a spectral model)");
}

LobeMaterial::LobeMaterial(LobeModel model, LobeMaterialMode mode, std::string modelName)
    : model_(std::move(model)), mode_(mode), modelName_(std::move(modelName)) {
  model_.validate();
  require(!(model_.hasHalfDifference() && mode_ == LobeMaterialMode::Prefiltered),
          "a lobe model with a half-difference table has no prefiltered form (use the lighting or reflectance mode)");
  rgbWeights_ = model_.rgbWeights();
  sharedShapes_ = sharesShapes(model_);
}

Rgb LobeMaterial::toRgb(const Eigen::VectorXd& channels) const { return (rgbWeights_ * channels).array(); }

bool LobeMaterial::viewIndependent() const {
  return mode_ == LobeMaterialMode::Prefiltered && !model_.variesWithView() && model_.allAboutMirror();
}

Rgb LobeMaterial::brdf(const Vec3& normal, const Vec3& view, const Vec3& light) const {
  const double nv = normal.dot(view), nl = normal.dot(light);
  if (!(nv > 0.0) || !(nl > 0.0)) return Rgb::Zero();
  return toRgb(channelValues(model_, sharedShapes_, pointTerms(model_, nv, LobeGeometry::of(normal, light, view))));
}

Rgb LobeMaterial::mirrorRgb(double nDotV) const {
  const double u = clampFinite(nDotV, 0.0, 1.0);
  return toRgb(channelValues(model_, sharedShapes_, pointTerms(model_, u, mirrorGeometry(u))));
}

Rgb LobeMaterial::unlit(const ShadingGeometry& g) const {
  if (mode_ != LobeMaterialMode::Reflectance) return Rgb::Zero();
  return mirrorRgb(g.normal.dot(g.view));
}

Rgb LobeMaterial::shade(const ShadingGeometry& g, const Vec3& light) const {
  switch (mode_) {
    case LobeMaterialMode::Reflectance:
      return Rgb::Zero();
    case LobeMaterialMode::Lighting:
      return brdf(g.normal, g.view, light) * std::max(0.0, g.normal.dot(light));
    case LobeMaterialMode::Prefiltered:
      break;
  }
  const double u = clampFinite(g.normal.dot(g.view), 0.0, 1.0);
  const double cosToMirror = g.reflected.dot(light);
  const LobeGeometry geometry = LobeGeometry::of(g.normal, light, g.view);
  Eigen::VectorXd values = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model_.channelCount()));
  for (std::size_t c = 0; c < model_.channelCount(); ++c) {
    for (std::size_t k = 0; k < model_.channels[c].lobes.size(); ++k) {
      const Lobe& lobe = model_.channels[c].lobes[k];
      // A mirror lobe depends on the reflected direction alone (also below the horizon of the
      // light, as Kautz & McCool's prefiltered map); a Lafortune lobe on its own axis.
      if (lobe.halfVector) {
        values[static_cast<Eigen::Index>(c)] +=
            halfVectorLobe(model_.weight(c, k, u), model_.fresnel(c, k, u), model_.exponent(c, k, u), geometry);
        continue;
      }
      const double cosToAxis = lobe.aboutMirror() ? cosToMirror : geometry.cosine(lobe.cxy);
      values[static_cast<Eigen::Index>(c)] +=
          normalizedLobe(model_.weight(c, k, u), model_.exponent(c, k, u), cosToAxis);
    }
  }
  return toRgb(values);
}

std::optional<std::vector<RadialLobe>> LobeMaterial::radialLobes(const Vec3& light, const Vec3&) const {
  if (!viewIndependent()) return std::nullopt;
  // Constant prefiltered lobes: one radial lobe about the light per channel and lobe.
  std::vector<RadialLobe> lobes;
  for (std::size_t c = 0; c < model_.channelCount(); ++c) {
    for (const auto& lobe : model_.channels[c].lobes) {
      const double n = lobe.exponent[0];
      const Rgb weight = lobe.weight[0] * rgbWeights_.col(static_cast<Eigen::Index>(c)).array();
      lobes.push_back({light, weight, [n](double x) { return normalizedLobe(1.0, n, x); }});
    }
  }
  return lobes;
}

}  // namespace brdfbake

namespace brdfbake {
namespace {

// Adds `lobe` to `lobes`, merged into one of the same shape and axis whose exponent is within a
// factor 1.5 (weights added, the exponent their weighted geometric mean): a spectral fit has a lobe
// per channel, and sampling needs only a density close to their sum.
void addMerged(std::vector<ReflectionLobe>& lobes, const ReflectionLobe& lobe) {
  if (!(lobe.weight > 0.0)) return;
  for (auto& other : lobes) {
    if (other.shape != lobe.shape || (other.axis - lobe.axis).squaredNorm() > 1e-18) continue;
    if (lobe.shape != ReflectionLobeShape::Cosine &&
        std::abs(std::log((lobe.parameter + 1.0) / (other.parameter + 1.0))) > std::log(1.5))
      continue;
    const double total = other.weight + lobe.weight;
    if (lobe.shape != ReflectionLobeShape::Cosine) {
      other.parameter =
          std::exp((other.weight * std::log(other.parameter + 1.0) + lobe.weight * std::log(lobe.parameter + 1.0)) /
                   total) -
          1.0;
    }
    other.weight = total;
    return;
  }
  lobes.push_back(lobe);
}

// A half-difference table's share for sampling at view cosine u: its value far from the highlight
// (theta_h = 45 degrees) as a diffuse albedo pi f, and what rises above that towards theta_h = 0 as a
// Blinn-Phong lobe whose exponent puts its half maximum where the table's rise falls to half (the
// first of theta_h = 0.05, 0.1, 0.2, ... 25.6 degrees), its weight C from f = C D / (4 u^2) at the peak.
void addTableLobes(const LobeModel& model, const LobeChannel& channel, double u, double luminance, const Vec3& normal,
                   std::vector<ReflectionLobe>& lobes, double& diffuse) {
  const double thetaV = std::acos(std::clamp(u, 0.0, 1.0));
  const auto value = [&](double thetaH) {
    return std::exp(
        HalfDifferenceBasis::at(model.halfDifference, thetaH, thetaV).logValue(channel.halfDifferenceCoefficients));
  };
  const double wide = value(radians(45.0)), rise = value(0.0) - wide;
  diffuse += kPi * wide * luminance;
  if (!(rise > 0.0)) return;
  double halfWidth = radians(32.0);
  for (double degreesOff = 0.05; degreesOff < 32.0; degreesOff *= 2.0) {
    if (value(radians(degreesOff)) - wide < 0.5 * rise) {
      halfWidth = radians(degreesOff);
      break;
    }
  }
  const double exponent = std::clamp(std::log(0.5) / std::log(std::cos(halfWidth)), kMinLobeExponent, kMaxLobeExponent);
  const double weight = rise * 4.0 * u * u / phongNormalization(exponent);
  addMerged(lobes, {ReflectionLobeShape::BlinnPhong, normal, exponent, weight * luminance});
}

}  // namespace

std::optional<std::vector<ReflectionLobe>> LobeMaterial::reflectionLobes(const ShadingGeometry& g) const {
  if (mode_ != LobeMaterialMode::Lighting) return std::nullopt;
  const double u = clampFinite(g.normal.dot(g.view), 0.0, 1.0);
  const Vec3 tangential = g.view - u * g.normal;  // v's component along the surface
  std::vector<ReflectionLobe> lobes;
  double diffuse = 0.0;
  for (std::size_t c = 0; c < model_.channelCount(); ++c) {
    const double channelLuminance = std::abs(luminance(rgbWeights_.col(static_cast<Eigen::Index>(c)).array()));
    const LobeChannel& channel = model_.channels[c];
    diffuse += channel.diffuse * channelLuminance;
    for (std::size_t k = 0; k < channel.lobes.size(); ++k) {
      const Lobe& lobe = channel.lobes[k];
      const double weight = model_.weight(c, k, u) * channelLuminance, exponent = model_.exponent(c, k, u);
      if (lobe.halfVector) {
        addMerged(lobes, {ReflectionLobeShape::BlinnPhong, g.normal, exponent,
                          weight + model_.fresnel(c, k, u) * channelLuminance});
        continue;
      }
      // Lafortune's axis a = c_xy (v - (n.v) n) + (n.v) n; c_xy = -1 is the mirrored view.
      const Vec3 a = lobe.cxy * tangential + u * g.normal;
      const double length = a.norm();
      if (!(length > 1e-12)) continue;
      const double growth = std::exp(std::min(exponent * std::log(length), 50.0));
      addMerged(lobes, {ReflectionLobeShape::PowerCosine, a / length, exponent, weight * growth});
    }
    if (model_.hasHalfDifference()) addTableLobes(model_, channel, u, channelLuminance, g.normal, lobes, diffuse);
  }
  if (diffuse > 0.0 || lobes.empty())
    lobes.push_back({ReflectionLobeShape::Cosine, g.normal, 0.0, std::max(diffuse, 1e-3)});
  return lobes;
}

}  // namespace brdfbake
