// The split-sum DFG table (dfg_table.hpp).
#include <brdfbake/brdf/split_sum.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/dfg_table.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace brdfbake {
namespace {

// Gauss-Legendre nodes and weights on [0, 1] (Newton's iteration on P_n from the Chebyshev guess).
struct Rule {
  std::vector<double> x, w;
};
Rule gaussLegendre(int n) {
  Rule rule;
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      if (n == 1) p1 = z, p0 = 1.0;
      derivative = n * (z * p1 - p0) / (z * z - 1.0);
      const double step = p1 / derivative;
      z -= step;
      if (std::abs(step) < 1e-15) break;
    }
    rule.x.push_back(0.5 * (1.0 - z));
    rule.w.push_back(1.0 / ((1.0 - z * z) * derivative * derivative));
  }
  return rule;
}

}  // namespace

std::string_view toString(DfgForm form) { return form == DfgForm::SingleScattering ? "single" : "multiscatter"; }

DfgForm parseDfgForm(std::string_view name) {
  return parseByName(name, std::array{DfgForm::SingleScattering, DfgForm::MultipleScattering}, "the DFG form");
}

void DfgOptions::validate() const {
  require(width >= 1 && width <= 4096 && height >= 1 && height <= 4096,
          "a DFG table is 1 to 4096 texels a side, got " + std::to_string(width) + " x " + std::to_string(height));
  require(
      points >= 1 && points <= 64 && panels >= 1 && panels <= 64,
      "DFG quadrature: 1 to 64 points and panels, got " + std::to_string(points) + " and " + std::to_string(panels));
}

namespace {

// u, the CDF of h's density D(h) (n.h) in theta_h, at cos^2 theta_h = c2 (inverse of the map below).
double cdfAt(double c2, double a2) { return (1.0 - c2) / (1.0 + (a2 - 1.0) * c2); }

// Adds the integral over u in [u0, u1] (each u: h's azimuth over [0, phi_max(u)], where n.l > 0).
// phi_max grows like a square root from a band's ends, and at the end where n.l reaches 0 the
// visibility changes over a range of n.l ~ alpha: u = u0 + (u1 - u0) (3t^2 - 2t^3) gathers the nodes
// at both ends and smooths the root away.
void integrateBand(double u0, double u1, double nv, double alpha, DfgForm form, const Rule& rule, int panels,
                   double& first, double& second) {
  const double a2 = alpha * alpha, sv = std::sqrt(std::max(0.0, 1.0 - nv * nv));
  for (int pu = 0; pu < panels; ++pu) {
    for (std::size_t iu = 0; iu < rule.x.size(); ++iu) {
      const double t = (pu + rule.x[iu]) / panels;
      const double u = u0 + (u1 - u0) * t * t * (3.0 - 2.0 * t);
      const double wu = rule.w[iu] * (u1 - u0) / panels * 6.0 * t * (1.0 - t);
      const double c2 = std::clamp((1.0 - u) / (1.0 + (a2 - 1.0) * u), 0.0, 1.0);  // cos^2 theta_h
      const double ch = std::sqrt(c2), shh = std::sqrt(1.0 - c2);
      // n.l = 2 (v.h)(n.h) - n.v > 0  <=>  cos phi > -nv cos(2 theta) / (sv sin(2 theta)).
      const double num = -nv * (2.0 * c2 - 1.0), den = sv * 2.0 * shh * ch;
      const double phiMax = den > 1e-300 ? std::acos(std::clamp(num / den, -1.0, 1.0)) : (num < 0.0 ? kPi : 0.0);
      if (!(phiMax > 0.0)) continue;
      for (int pp = 0; pp < panels; ++pp) {
        for (std::size_t ip = 0; ip < rule.x.size(); ++ip) {
          // phi = phi_max (1 - (1 - t)^2): nodes gather near phi_max, where n.l rises from 0 and V
          // changes fast at grazing view.
          const double tp = (pp + rule.x[ip]) / panels, phi = phiMax * (1.0 - (1.0 - tp) * (1.0 - tp));
          const double wp = rule.w[ip] / panels * 2.0 * phiMax * (1.0 - tp);
          const double vh = sv * shh * std::cos(phi) + nv * ch, nl = 2.0 * vh * ch - nv;
          if (!(nl > 0.0) || !(vh > 0.0)) continue;
          // D V F (n.l) / pdf(l), pdf(l) = D (n.h) / (4 v.h); 1/pi: azimuth [0, pi] of [0, 2 pi] by symmetry.
          const double w = wu * wp / kPi * 4.0 * ggxSmithCorrelatedVisibility(nv, nl, alpha) * nl * vh / ch;
          const double fc = schlickWeight(vh);
          first += w * (form == DfgForm::SingleScattering ? 1.0 - fc : fc);
          second += w * (form == DfgForm::SingleScattering ? fc : 1.0);
        }
      }
    }
  }
}

}  // namespace

DfgTerms dfgTerms(double cosView, double roughness, DfgForm form, int points, int panels) {
  require(cosView > 0.0 && cosView <= 1.0 && roughness >= 0.0 && roughness <= 1.0,
          "DFG terms need n.v in (0, 1] and roughness in [0, 1]");
  static thread_local Rule rule;
  if (static_cast<int>(rule.x.size()) != points) rule = gaussLegendre(points);
  const double alpha = std::max(roughness * roughness, 1e-7), a2 = alpha * alpha;
  // h has density D(h) (n.h) over solid angle: u = its CDF in theta_h, uniform in azimuth. With
  // theta_v the view angle, every azimuth of h keeps l above the horizon for theta_h <= pi/4 -
  // theta_v/2, some for theta_h up to pi/4 + theta_v/2, none beyond: the integrand in u has kinks
  // there, so each band is its own Gauss-Legendre product rule.
  const double thetaV = std::acos(cosView);
  const double c1 = std::cos(0.25 * kPi - 0.5 * thetaV), c2 = std::cos(0.25 * kPi + 0.5 * thetaV);
  const double u1 = cdfAt(c1 * c1, a2), u2 = cdfAt(c2 * c2, a2);
  double first = 0.0, second = 0.0;
  integrateBand(0.0, u1, cosView, alpha, form, rule, panels, first, second);
  if (u2 > u1) integrateBand(u1, u2, cosView, alpha, form, rule, panels, first, second);
  return {first, second};
}

Image dfgTable(const DfgOptions& options, const Context& context) {
  options.validate();
  const int w = options.width, h = options.height;
  Image image(w, h, Rgba(0, 0, 0, 1));
  tbb::task_arena arena(context.arenaThreads());
  arena.execute([&] {
    tbb::parallel_for(0, h, [&](int j) {
      context.checkCancelled();
      const double roughness = (j + 0.5) / h;
      for (int i = 0; i < w; ++i) {
        const DfgTerms t = dfgTerms((i + 0.5) / w, roughness, options.form, options.points, options.panels);
        image.set(i, j, Rgba(t.first, t.second, 0.0, 1.0));
      }
    });
  });
  const bool single = options.form == DfgForm::SingleScattering;
  image.metadata = {
      {"convention_version", kConventionVersion},
      {"dfg_table",
       {{"form", std::string(toString(options.form))},
        {"width", w},
        {"height", h},
        {"x", "n.v = (i + 0.5) / " + std::to_string(w) + " at texel column i"},
        {"y",
         "perceptual roughness R = (j + 0.5) / " + std::to_string(h) + " at texel row j (row 0 first); alpha = R^2"},
        {"lookup", "texture(dfg, vec2(n.v, R)), rows uploaded in file order"},
        {"channels", single ? "R = DFG1 = ∫ (1 - Fc) D V (n.l), G = DFG2 = ∫ Fc D V (n.l), Fc = (1 - v.h)^5"
                            : "R = DFG1 = ∫ Fc D V (n.l), G = DFG2 = ∫ D V (n.l), Fc = (1 - v.h)^5"},
        {"formula", single ? "specular albedo E = f0 * DFG1 + f90 * DFG2"
                           : "E = mix(DFG1, DFG2, f0); DFG2 is the white single-scattering albedo"},
        {"brdf", "GGX D, Smith height-correlated V = G2 / (4 n.l n.v) (Heitz 2014 Eq. 99), Schlick F"}}}};
  return image;
}

WriteReport writeDfgTable(const Image& table, const std::filesystem::path& path, const WriteOptions& options) {
  const ImageFormat format = imageFormatFor(path);
  if (format == ImageFormat::Png || format == ImageFormat::RadianceHdr) {
    throw Error(Error::Kind::InvalidArgument,
                path.string() +
                    ": a DFG table is two linear channels; write it as .exr, .tif, .ktx2, .ktx or .dds "
                    "(PNG stores 8-bit sRGB, Radiance HDR shares one exponent between channels)");
  }
  return writeImage(table, path, options);
}

}  // namespace brdfbake
