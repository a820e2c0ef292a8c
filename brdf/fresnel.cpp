#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>

#include <limits>
#include <sstream>

namespace brdfbake {
namespace {

std::string describeNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string describeRgb(const Rgb& c) {
  std::ostringstream out;
  out << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]";
  return out.str();
}

// Reduces the spectra F(lambda, c) to an RGB table over c = i / (size - 1).
template <class Reflectance>
FresnelTerm spectralTable(std::span<const double> wavelengthsNm, const Reflectance& reflectance) {
  const SpectrumToRgb toRgb(wavelengthsNm);
  const std::vector<double> ones(wavelengthsNm.size(), 1.0);
  const Rgb white = toRgb.linearSrgb(ones);
  constexpr int kSize = 1025;
  std::vector<Rgb> table(kSize);
  std::vector<double> spectrum(wavelengthsNm.size());
  for (int i = 0; i < kSize; ++i) {
    const double c = static_cast<double>(i) / (kSize - 1);
    for (std::size_t j = 0; j < spectrum.size(); ++j) spectrum[j] = reflectance(j, c);
    table[static_cast<std::size_t>(i)] = (toRgb.linearSrgb(spectrum) / white).max(0.0).min(1.0);
  }
  return FresnelTerm::table(std::move(table));
}

}  // namespace

double iorFromF0(double f0) {
  require(std::isfinite(f0) && f0 >= 0.0 && f0 <= 1.0, "f0 must be in [0, 1], got " + std::to_string(f0));
  if (f0 >= 1.0) return std::numeric_limits<double>::infinity();
  const double r = std::sqrt(f0);
  return (1.0 + r) / (1.0 - r);
}

FresnelTerm FresnelTerm::dielectric(const Rgb& eta) {
  require(allFinite(eta) && (eta >= kMinFresnelIndex).all() && (eta <= kMaxFresnelIndex).all(),
          "index of refraction must be in [" + describeNumber(kMinFresnelIndex) + ", " +
              describeNumber(kMaxFresnelIndex) + "], got " + describeRgb(eta));
  FresnelTerm f;
  f.kind_ = Kind::Dielectric;
  f.eta_ = eta;
  return f;
}

FresnelTerm FresnelTerm::fromF0(const Rgb& f0) {
  require(allFinite(f0) && (f0 >= 0.0).all() && (f0 <= 1.0).all(), "f0 must be in [0, 1], got " + describeRgb(f0));
  FresnelTerm f;
  f.kind_ = Kind::Dielectric;
  for (int i = 0; i < 3; ++i) f.eta_[i] = iorFromF0(f0[i]);
  return f;
}

FresnelTerm FresnelTerm::conductor(const Rgb& n, const Rgb& k) {
  require(allFinite(n) && (n >= kMinFresnelIndex).all() && (n <= kMaxFresnelIndex).all(),
          "n must be in [" + describeNumber(kMinFresnelIndex) + ", " + describeNumber(kMaxFresnelIndex) + "], got " +
              describeRgb(n));
  require(allFinite(k) && (k >= 0.0).all() && (k <= kMaxFresnelIndex).all(),
          "k must be in [0, " + describeNumber(kMaxFresnelIndex) + "], got " + describeRgb(k));
  FresnelTerm f;
  f.kind_ = Kind::Conductor;
  f.eta_ = n;
  f.k_ = k;
  return f;
}

FresnelTerm FresnelTerm::table(std::vector<Rgb> valuesOverCos) {
  require(valuesOverCos.size() >= 2, "a Fresnel table needs at least 2 entries");
  for (const auto& v : valuesOverCos) {
    require(allFinite(v) && (v >= 0.0).all() && (v <= 1.0).all(), "Fresnel table values must be in [0, 1]");
  }
  FresnelTerm f;
  f.kind_ = Kind::Table;
  f.table_ = std::move(valuesOverCos);
  f.eta_ = Rgb::Zero();
  return f;
}

FresnelTerm FresnelTerm::spectralConductor(std::span<const double> wavelengthsNm, std::span<const double> n,
                                           std::span<const double> k) {
  require(n.size() == wavelengthsNm.size() && k.size() == wavelengthsNm.size(),
          "spectral n and k need one value per wavelength (" + std::to_string(wavelengthsNm.size()) + ")");
  for (std::size_t j = 0; j < n.size(); ++j) {
    require(
        std::isfinite(n[j]) && n[j] >= kMinFresnelIndex && n[j] <= kMaxFresnelIndex,
        "spectral n must be in [" + describeNumber(kMinFresnelIndex) + ", " + describeNumber(kMaxFresnelIndex) + "]");
    require(std::isfinite(k[j]) && k[j] >= 0.0 && k[j] <= kMaxFresnelIndex,
            "spectral k must be in [0, " + describeNumber(kMaxFresnelIndex) + "]");
  }
  return spectralTable(wavelengthsNm, [&](std::size_t j, double c) { return fresnelConductor(c, n[j], k[j]); });
}

FresnelTerm FresnelTerm::spectralF0(std::span<const double> wavelengthsNm, std::span<const double> f0) {
  require(f0.size() == wavelengthsNm.size(),
          "spectral f0 needs one value per wavelength (" + std::to_string(wavelengthsNm.size()) + ")");
  std::vector<double> eta(f0.size());
  for (std::size_t j = 0; j < f0.size(); ++j) eta[j] = iorFromF0(f0[j]);
  return spectralTable(
      wavelengthsNm, [&](std::size_t j, double c) { return std::isinf(eta[j]) ? 1.0 : fresnelDielectric(c, eta[j]); });
}

FresnelTerm FresnelTerm::schlick(const Rgb& f0) {
  for (int i = 0; i < 3; ++i) {
    require(std::isfinite(f0[i]) && f0[i] >= 0.0 && f0[i] <= 1.0, "Schlick f0 must be in [0, 1] per channel");
  }
  FresnelTerm term;
  term.kind_ = Kind::Schlick;
  term.eta_ = f0;
  return term;
}

Rgb FresnelTerm::operator()(double cosTheta) const {
  const double c = clampFinite(cosTheta, 0.0, 1.0);
  Rgb f;
  switch (kind_) {
    case Kind::Dielectric:
      for (int i = 0; i < 3; ++i) f[i] = std::isinf(eta_[i]) ? 1.0 : fresnelDielectric(c, eta_[i]);
      break;
    case Kind::Conductor:
      for (int i = 0; i < 3; ++i) f[i] = fresnelConductor(c, eta_[i], k_[i]);
      break;
    case Kind::Schlick:
      for (int i = 0; i < 3; ++i) f[i] = fresnelSchlick(c, eta_[i]);
      break;
    case Kind::Table: {
      const double x = c * static_cast<double>(table_.size() - 1);
      const auto j = std::min(static_cast<std::size_t>(x), table_.size() - 2);
      const double w = x - static_cast<double>(j);
      f = table_[j] + w * (table_[j + 1] - table_[j]);
      break;
    }
  }
  return f;
}

std::vector<Rgb> fresnelTable(const FresnelTerm& fresnel, int size) {
  require(size >= 1, "Fresnel table size must be >= 1, got " + std::to_string(size));
  std::vector<Rgb> table(static_cast<std::size_t>(size));
  for (int i = 0; i < size; ++i) table[static_cast<std::size_t>(i)] = fresnel((i + 0.5) / size);
  return table;
}

FresnelCombine parseFresnelCombine(std::string_view name) {
  return parseByName(name, std::array{FresnelCombine::Add, FresnelCombine::Mix}, "combine");
}

std::string_view toString(FresnelCombine combine) { return combine == FresnelCombine::Add ? "add" : "mix"; }

}  // namespace brdfbake
