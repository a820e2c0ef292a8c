#pragma once
// The lobe formula of docs/fitting.md typed out for the tests, independently of the library: a
// fit.json's numbers turned into a BRDF value, with Lafortune et al. 1997 Eq. 4 as its lobes.
#include <brdfbake/core/math.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace brdfbake::test {

/// (sin theta cos phi, sin theta sin phi, cos theta): the Cornell convention.
inline Vec3 cornellDirection(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// Lafortune et al. 1997 Eq. 4 with C_x = C_y = cxy, C_z = 1, scaled as brdf/lobes.hpp documents:
/// C (n + 2) / (2 pi) max(0, cxy (l_x v_x + l_y v_y) + l_z v_z)^n.
inline double lafortuneByHand(double c, double n, double cxy, const Vec3& l, const Vec3& v) {
  const double x = cxy * (l.x() * v.x() + l.y() * v.y()) + l.z() * v.z();
  return x > 0.0 ? c * (n + 2.0) / (2.0 * kPi) * std::pow(x, n) : 0.0;
}

/// The BRDF of channel `channel` of the fit.json document `fit` at (wi, wo): diffuse / pi plus each
/// lobe, its weight and exponent blended over the elevation range when the model's elevation is
/// "varying" (log-cosine parameter t; weights (1-t)^2, 2t(1-t), t^2 of the three values' logs);
/// a lobe without "cxy" is the mirror lobe (cxy = -1).
inline double fitFormula(const nlohmann::json& fit, std::size_t channel, const Vec3& wi, const Vec3& wo) {
  const auto& ch = fit["channels"][channel];
  const double minCos = fit["model"]["elevation_range"]["min_cos"], maxCos = fit["model"]["elevation_range"]["max_cos"];
  const bool varying = fit["model"]["elevation"] == "varying";
  const double t = maxCos > minCos ? std::clamp(std::log(wo.z() / minCos) / std::log(maxCos / minCos), 0.0, 1.0) : 0.0;
  auto parameter = [&](const nlohmann::json& p) {
    if (!varying) return p[0].get<double>();
    return std::pow(p[0].get<double>(), (1 - t) * (1 - t)) * std::pow(p[1].get<double>(), 2 * t * (1 - t)) *
           std::pow(p[2].get<double>(), t * t);
  };
  double f = ch["diffuse"].get<double>() / kPi;
  for (const auto& lobe : ch["lobes"]) {
    const double cxy = lobe.contains("cxy") ? lobe["cxy"].get<double>() : -1.0;
    f += lafortuneByHand(parameter(lobe["weight"]), parameter(lobe["exponent"]), cxy, wi, wo);
  }
  return f;
}

}  // namespace brdfbake::test
