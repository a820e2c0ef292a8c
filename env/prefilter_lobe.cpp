#include <brdfbake/brdf/blinn_conversion.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/env/prefilter_lobe.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace brdfbake {

// The lobe and its tables over the angle theta to the axis: theta_k = pi (k / K)^2, dense near the
// peak (spacing 1.2e-8 rad at 0) and still fine at the horizon (3.8e-4 rad), so the same grid
// resolves Phong 1e6 and the hemisphere.
struct PrefilterLobe::Data {
  LobeKind kind = LobeKind::Mirror;
  std::string name, description;
  double exponent = 0.0;                  // Phong
  double alpha = 0.0;                     // GGX
  double roughness = 0.0;                 // GGX perceptual roughness, as given
  double scale = 1.0;                     // normalisation factor applied to the raw weight
  double mass = 0.0;                      // analytic where known, else the grid's integral
  std::vector<double> theta, cumulative;  // cumulative mass over theta (scaled to `mass` at pi)

  double rawWeight(double c) const {
    switch (kind) {
      case LobeKind::Mirror:
        return 0.0;
      case LobeKind::Irradiance:
        return c > 0.0 ? c : 0.0;
      case LobeKind::Phong:
        return c > 0.0 ? (exponent == 0.0 ? 1.0 : std::pow(c, exponent)) : 0.0;
      case LobeKind::Ggx: {
        if (!(c > 0.0)) return 0.0;
        const double nh2 = 0.5 * (1.0 + c);  // (n.h)^2 with n = r, h = normalize(r + l)
        const double f = (alpha - 1.0) * ((alpha + 1.0) * nh2) + 1.0;
        return alpha * alpha / (kPi * f * f) * c;
      }
    }
    return 0.0;
  }
};

namespace {

constexpr int kGrid = 16384;

std::shared_ptr<PrefilterLobe::Data> finish(std::shared_ptr<PrefilterLobe::Data> d, double analyticMass,
                                            bool normalise) {
  if (d->kind == LobeKind::Mirror) {
    d->mass = 1.0;
    return d;
  }
  d->theta.resize(kGrid + 1);
  d->cumulative.resize(kGrid + 1);
  std::vector<double> integrand(kGrid + 1);
  for (int k = 0; k <= kGrid; ++k) {
    const double s = static_cast<double>(k) / kGrid;
    d->theta[k] = kPi * s * s;
    const double value = d->rawWeight(std::cos(d->theta[k]));
    if (!std::isfinite(value) || value < 0.0) {
      throw Error(Error::Kind::InvalidArgument, "lobe " + d->name + ": weight must be finite and >= 0, got " +
                                                    std::to_string(value) + " at cos " +
                                                    std::to_string(std::cos(d->theta[k])));
    }
    integrand[k] = kTwoPi * value * std::sin(d->theta[k]);
  }
  d->cumulative[0] = 0.0;
  for (int k = 1; k <= kGrid; ++k) {
    d->cumulative[k] = d->cumulative[k - 1] + 0.5 * (integrand[k] + integrand[k - 1]) * (d->theta[k] - d->theta[k - 1]);
  }
  const double gridMass = d->cumulative[kGrid];
  if (!(gridMass > 0.0)) throw Error(Error::Kind::InvalidArgument, "lobe " + d->name + ": weight integrates to 0");
  if (analyticMass > 0.0) {
    d->scale = 1.0;
    d->mass = analyticMass;
  } else if (normalise) {
    d->scale = 1.0 / gridMass;
    d->mass = 1.0;
  } else {
    d->scale = 1.0;
    d->mass = gridMass;
  }
  // The cumulative table describes the distribution; rescale it to the mass the lobe reports.
  const double toMass = d->mass / gridMass;
  for (double& c : d->cumulative) c *= toMass;
  return d;
}

double parseNumber(std::string_view text, std::string_view lobe) {
  if (const auto value = finiteNumberIn(text)) return *value;
  throw Error(Error::Kind::InvalidArgument,
              "lobe '" + printable(lobe, 60) + "': '" + printable(text, 40) + "' is not a number");
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

}  // namespace

PrefilterLobe PrefilterLobe::mirror() {
  auto d = std::make_shared<Data>();
  d->kind = LobeKind::Mirror;
  d->name = "mirror";
  d->description = "mirror (the environment resampled)";
  return PrefilterLobe(finish(d, 1.0, false));
}

PrefilterLobe PrefilterLobe::irradiance() {
  auto d = std::make_shared<Data>();
  d->kind = LobeKind::Irradiance;
  d->name = "irradiance";
  d->description = "radiance-equivalent irradiance E(n)/pi = (1/pi) ∫ L max(0, n.l) dω, indexed by the normal";
  auto lobe = finish(d, 1.0, false);
  lobe->scale = 1.0 / kPi;
  return PrefilterLobe(lobe);
}

PrefilterLobe PrefilterLobe::phong(double exponent) {
  require(std::isfinite(exponent) && exponent >= 0.0 && exponent <= 1e6,
          "phong exponent must be in [0, 1e6], got " + formatNumber(exponent));
  auto d = std::make_shared<Data>();
  d->kind = LobeKind::Phong;
  d->exponent = exponent;
  d->name = "phong:" + formatNumber(exponent);
  d->description = "normalised Phong (N + 1)/(2 pi) max(0, r.l)^N, N = " + formatNumber(exponent);
  auto lobe = finish(d, 1.0, false);
  lobe->scale = (exponent + 1.0) / kTwoPi;
  return PrefilterLobe(lobe);
}

PrefilterLobe PrefilterLobe::blinn(double blinnExponent) {
  require(std::isfinite(blinnExponent) && blinnExponent >= 0.0 && blinnExponent <= 4e6,
          "blinn exponent must be in [0, 4e6], got " + formatNumber(blinnExponent));
  PrefilterLobe lobe = phong(blinnExponent / 4.0);
  auto d = std::make_shared<Data>(*lobe.data_);
  d->name = "blinn:" + formatNumber(blinnExponent);
  d->description = "Blinn-Phong N' = " + formatNumber(blinnExponent) +
                   " as normalised Phong N = N'/4 = " + formatNumber(blinnExponent / 4.0) + " (policy " +
                   std::string(toString(BlinnConversion::FourN)) + ")";
  return PrefilterLobe(d);
}

PrefilterLobe PrefilterLobe::ggx(double roughness) {
  require(std::isfinite(roughness) && roughness >= 0.01 && roughness <= 1.0,
          "ggx roughness must be in [0.01, 1] (use the mirror lobe for 0), got " + formatNumber(roughness));
  auto d = std::make_shared<Data>();
  d->kind = LobeKind::Ggx;
  d->alpha = roughness * roughness;
  d->roughness = roughness;
  d->name = "ggx:" + formatNumber(roughness);
  d->description = "GGX split-sum lobe D(h) max(0, n.l) with n = v = r, perceptual roughness " +
                   formatNumber(roughness) + " (alpha " + formatNumber(d->alpha) + "), normalised";
  return PrefilterLobe(finish(d, 0.0, true));
}

PrefilterLobe PrefilterLobe::parse(std::string_view text, const std::filesystem::path& baseDirectory) {
  const std::string accepted = "accepted: mirror, irradiance, phong:N, blinn:N, ggx:ROUGHNESS, lobes:FIT.json";
  const auto colon = text.find(':');
  const std::string_view head = text.substr(0, colon);
  const std::string_view tail = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
  auto needsArgument = [&](bool needs) {
    if (needs && tail.empty()) {
      throw Error(Error::Kind::InvalidArgument,
                  "lobe '" + printable(text, 60) + "' needs a parameter after ':' (" + accepted + ")");
    }
    if (!needs && colon != std::string_view::npos) {
      throw Error(Error::Kind::InvalidArgument,
                  "lobe '" + printable(head, 60) + "' takes no parameter (" + accepted + ")");
    }
  };
  if (head == "mirror") return needsArgument(false), mirror();
  if (head == "irradiance" || head == "diffuse") return needsArgument(false), irradiance();
  if (head == "phong") return needsArgument(true), phong(parseNumber(tail, text));
  if (head == "blinn") return needsArgument(true), blinn(parseNumber(tail, text));
  if (head == "ggx") return needsArgument(true), ggx(parseNumber(tail, text));
  if (head == "lobes") {
    needsArgument(true);
    const std::filesystem::path file = std::filesystem::path(tail).is_absolute() || baseDirectory.empty()
                                           ? std::filesystem::path(tail)
                                           : baseDirectory / std::filesystem::path(tail);
    // Fitted lobes are RGB-weighted sums of Phong lobes, not one scalar lobe: the CLI and specs read
    // the fit.json (readFitFile) and call prefilterLobeModel.
    throw Error(Error::Kind::InvalidArgument, "lobe 'lobes:" + printable(file.string()) +
                                                  "' is a fitted lobe model: read it with readFitFile and prefilter it "
                                                  "with prefilterLobeModel");
  }
  throw Error(Error::Kind::InvalidArgument, "unknown lobe '" + printable(text, 60) + "' (" + accepted + ")");
}

LobeKind PrefilterLobe::kind() const { return data_->kind; }
const std::string& PrefilterLobe::name() const { return data_->name; }
std::string PrefilterLobe::description() const { return data_->description; }
double PrefilterLobe::phongExponent() const { return data_->kind == LobeKind::Phong ? data_->exponent : 0.0; }
double PrefilterLobe::ggxAlpha() const { return data_->alpha; }
double PrefilterLobe::ggxRoughness() const { return data_->roughness; }
double PrefilterLobe::mass() const { return data_->mass; }

double PrefilterLobe::weight(double c) const { return data_->scale * data_->rawWeight(c); }

double PrefilterLobe::sampleAngle(double u) const {
  const auto& cdf = data_->cumulative;
  if (cdf.empty()) return 0.0;
  const double target = std::clamp(u, 0.0, 1.0) * cdf.back();
  const auto it = std::lower_bound(cdf.begin(), cdf.end(), target);
  if (it == cdf.begin()) return 0.0;
  if (it == cdf.end()) return data_->theta.back();
  const std::size_t k = static_cast<std::size_t>(it - cdf.begin());
  const double span = cdf[k] - cdf[k - 1];
  const double f = span > 0.0 ? (target - cdf[k - 1]) / span : 0.0;
  return data_->theta[k - 1] + f * (data_->theta[k] - data_->theta[k - 1]);
}

double PrefilterLobe::halfMassAngle() const { return sampleAngle(0.5); }

double PrefilterLobe::width() const { return halfMassAngle() / std::sqrt(2.0 * std::log(2.0)); }

double PrefilterLobe::tailAngle(double fraction) const {
  if (data_->cumulative.empty()) return 0.0;
  return fraction <= 0.0 ? kPi : sampleAngle(1.0 - fraction);
}

std::vector<double> PrefilterLobe::zonalCoefficients(int maxOrder) const {
  require(maxOrder >= 0, "zonal coefficients need an order >= 0");
  std::vector<double> lambda(maxOrder + 1, 0.0);
  if (data_->kind == LobeKind::Mirror) {
    std::fill(lambda.begin(), lambda.end(), 1.0);
    return lambda;
  }
  // lambda_l = 2 pi ∫ w(cos t) P_l(cos t) sin t dt, trapezoid on the lobe's grid (P_l by recurrence),
  // over the grid points where the integrand is non-zero (not beyond the lobe's support: a Phong
  // lobe's back hemisphere, the far tail). The recurrence runs over l outside and the points inside,
  // so the inner loops are independent across points (vectorised).
  std::vector<double> c, weight;
  for (int k = 0; k <= kGrid; ++k) {
    const double t = data_->theta[k];
    const double f = kTwoPi * this->weight(std::cos(t)) * std::sin(t);
    if (f == 0.0) continue;
    const double h0 = k > 0 ? data_->theta[k] - data_->theta[k - 1] : 0.0;
    const double h1 = k < kGrid ? data_->theta[k + 1] - data_->theta[k] : 0.0;
    c.push_back(std::cos(t));
    weight.push_back(0.5 * (h0 + h1) * f);
  }
  const std::size_t n = c.size();
  std::vector<double> previous(n, 0.0), current(n, 1.0);  // P_{l-1}, P_l at l = 0
  for (int l = 0; l <= maxOrder; ++l) {
    if (l == 1) previous.swap(current), current = c;  // P_0 = 1, P_1 = c
    if (l >= 2) {
      const double a = (2.0 * l - 1.0) / l, b = (l - 1.0) / l;
      double* __restrict p0 = previous.data();
      double* __restrict p1 = current.data();
      const double* __restrict x = c.data();
      for (std::size_t k = 0; k < n; ++k) {
        const double next = a * x[k] * p1[k] - b * p0[k];
        p0[k] = p1[k], p1[k] = next;
      }
    }
    double sum[4] = {0.0, 0.0, 0.0, 0.0};  // four partial sums: independent additions
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4)
      for (int j = 0; j < 4; ++j) sum[j] += weight[k + j] * current[k + j];
    for (; k < n; ++k) sum[0] += weight[k] * current[k];
    lambda[l] = (sum[0] + sum[1]) + (sum[2] + sum[3]);
  }
  // Match lambda_0 to the reported mass, so a constant environment comes out exactly.
  const double toMass = lambda[0] > 0.0 ? data_->mass / lambda[0] : 1.0;
  for (double& value : lambda) value *= toMass;
  return lambda;
}

}  // namespace brdfbake
