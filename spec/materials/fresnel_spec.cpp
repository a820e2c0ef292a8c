// The "fresnel" object (shared by cook_torrance and fresnel) and the "fresnel" material.
#include <brdfbake/brdf/fresnel.hpp>

#include <optional>

#include "registry_entries.hpp"

namespace brdfbake::materials {
namespace {

// A colour whose channels must also satisfy `valid` (named in `expectation`).
// (Read as numbers, not colours: an index is no colour, and its own range applies.)
template <class Valid>
Rgb checkedColor(JsonObjectReader& r, const std::string& key, Valid valid, const std::string& expectation) {
  const nlohmann::json& value = r.require(key);
  Rgb c;
  if (value.is_array() && value.size() == 3) {
    for (int i = 0; i < 3; ++i)
      c[i] = JsonObjectReader::asNumber(value[i], r.child(key) + "[" + std::to_string(i) + "]");
  } else if (value.is_number()) {
    c.setConstant(JsonObjectReader::asNumber(value, r.child(key)));
  } else {
    throw specError(r.child(key), "must be [r, g, b] or one number, got " + describe(value));
  }
  for (int i = 0; i < 3; ++i) {
    if (!(valid(c[i]) && c[i] >= 0.0))
      throw specError(r.child(key), "must be " + expectation + ", got " + describe(value));
  }
  return c;
}

// Spectral samples: more than any measured spectrum has (1 nm steps over 380-780 nm are 401).
constexpr std::size_t kMaxWavelengths = 1024;

std::vector<double> numbers(JsonObjectReader& r, const std::string& key) {
  const auto& array = r.array(key, kMaxWavelengths);
  std::vector<double> values;
  for (std::size_t i = 0; i < array.size(); ++i) {
    values.push_back(JsonObjectReader::asNumber(array[i], r.child(key) + "[" + std::to_string(i) + "]"));
  }
  if (values.empty()) throw specError(r.child(key), "must not be empty");
  return values;
}

FresnelTerm parseSpectral(JsonObjectReader& s) {
  const std::vector<double> wavelengths = numbers(s, "wavelengths_nm");
  for (std::size_t i = 0; i < wavelengths.size(); ++i) {
    if (!(wavelengths[i] > 0.0 && wavelengths[i] <= 1e5) || (i > 0 && !(wavelengths[i] > wavelengths[i - 1]))) {
      throw specError(s.child("wavelengths_nm") + "[" + std::to_string(i) + "]",
                      "wavelengths must increase strictly, each in (0, 1e5] nm");
    }
  }
  const bool conductor = s.has("n") || s.has("k");
  if (conductor == s.has("f0"))
    throw specError(s.path(), "give either \"n\" with \"k\", or \"f0\" (one value per wavelength)");
  auto sameSize = [&](const std::string& key, const std::vector<double>& values) {
    if (values.size() != wavelengths.size()) {
      throw specError(s.child(key), "needs one value per wavelength (" + std::to_string(wavelengths.size()) +
                                        "), got " + std::to_string(values.size()));
    }
  };
  if (conductor) {
    const auto n = numbers(s, "n"), k = numbers(s, "k");
    sameSize("n", n);
    sameSize("k", k);
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!(n[i] >= kMinFresnelIndex && n[i] <= kMaxFresnelIndex))
        throw specError(s.child("n") + "[" + std::to_string(i) + "]", "must be in [0.001, 1000] (docs/limits.md)");
      if (!(k[i] >= 0.0 && k[i] <= kMaxFresnelIndex))
        throw specError(s.child("k") + "[" + std::to_string(i) + "]", "must be in [0, 1000] (docs/limits.md)");
    }
    s.finish();
    return FresnelTerm::spectralConductor(wavelengths, n, k);
  }
  const auto f0 = numbers(s, "f0");
  sameSize("f0", f0);
  for (std::size_t i = 0; i < f0.size(); ++i) {
    if (!(f0[i] >= 0.0 && f0[i] <= 1.0))
      throw specError(s.child("f0") + "[" + std::to_string(i) + "]", "must be in [0, 1]");
  }
  s.finish();
  return FresnelTerm::spectralF0(wavelengths, f0);
}

}  // namespace

FresnelTerm parseFresnelTerm(JsonObjectReader& owner, const std::string& key) {
  JsonObjectReader f = owner.object(key);
  const bool ior = f.has("ior"), f0 = f.has("f0"), nk = f.has("n") || f.has("k"), spectral = f.has("spectral");
  const bool schlick = f.has("schlick");
  if (ior + f0 + nk + spectral + schlick != 1) {
    throw specError(f.path(),
                    "give exactly one of {\"ior\": eta}, {\"f0\": [r, g, b]}, {\"schlick\": [r, g, b]}, "
                    "{\"n\": [r, g, b], \"k\": [r, g, b]}"
                    " or {\"spectral\": {\"wavelengths_nm\": [...], \"n\": [...], \"k\": [...]}}");
  }
  std::optional<FresnelTerm> term;
  try {
    if (ior) {
      term = FresnelTerm::dielectric(checkedColor(
          f, "ior", [](double v) { return v >= kMinFresnelIndex && v <= kMaxFresnelIndex; },
          "in [0.001, 1000] (docs/limits.md)"));
    } else if (schlick) {
      term = FresnelTerm::schlick(checkedColor(
          f, "schlick", [](double v) { return v <= 1.0; }, "in [0, 1]"));
    } else if (f0) {
      term = FresnelTerm::fromF0(checkedColor(
          f, "f0", [](double v) { return v <= 1.0; }, "in [0, 1]"));
    } else if (nk) {
      if (!f.has("n") || !f.has("k")) throw specError(f.path(), "\"n\" and \"k\" go together (complex index n + i k)");
      const Rgb n = checkedColor(
          f, "n", [](double v) { return v >= kMinFresnelIndex && v <= kMaxFresnelIndex; },
          "in [0.001, 1000] (docs/limits.md)");
      const Rgb k = checkedColor(
          f, "k", [](double v) { return v <= kMaxFresnelIndex; }, "in [0, 1000] (docs/limits.md)");
      term = FresnelTerm::conductor(n, k);
    } else {
      JsonObjectReader s = f.object("spectral");
      term = parseSpectral(s);
    }
  } catch (const Error& e) {
    if (e.kind() == Error::Kind::InvalidInput) throw;
    throw specError(f.path(), e.what());
  }
  f.finish();
  return *term;
}

std::shared_ptr<const Material> parseFresnel(JsonObjectReader& m, const MaterialContext&) {
  FresnelTerm fresnel = parseFresnelTerm(m, "fresnel");
  const FresnelCombine combine = m.parsed("combine", parseFresnelCombine, "add");
  return std::make_shared<FresnelMaterial>(std::move(fresnel), combine);
}

}  // namespace brdfbake::materials
