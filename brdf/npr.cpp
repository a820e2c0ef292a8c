#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>

#include <algorithm>
#include <limits>

namespace brdfbake {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Standard normal CDF and density.
double normalCdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }
double normalPdf(double x) { return std::isinf(x) ? 0.0 : std::exp(-0.5 * x * x) / std::sqrt(kTwoPi); }

// A smoothed step: Phi(x / sigma), or the step itself for sigma = 0.
double softStep(double x, double sigma) {
  if (sigma > 0.0) return normalCdf(x / sigma);
  return x > 0.0 ? 1.0 : (x < 0.0 ? 0.0 : 0.5);
}

void checkColor(const Rgb& c, const std::string& what) {
  require(allFinite(c) && (c >= 0.0).all(), what + " must be finite and >= 0");
}

double fraction(double u) { return u - std::floor(u); }

}  // namespace

ViewFrame viewFrame(const Vec3& view) {
  Vec3 right = Vec3::UnitY().cross(view);
  const double norm = right.norm();
  right = norm > 1e-9 ? Vec3(right / norm) : Vec3::UnitX();
  return {right, view.cross(right).normalized()};
}

double viewAngleDegrees(double nDotV) { return degrees(std::acos(clampFinite(nDotV, 0.0, 1.0))); }

// ---- colour gradient ---------------------------------------------------------------------------

ColorGradient::ColorGradient(std::vector<ColorStop> stops, double blurDegrees)
    : stops_(std::move(stops)), blur_(blurDegrees) {
  require(!stops_.empty(), "a gradient needs at least one colour stop");
  require(std::isfinite(blur_) && blur_ >= 0.0, "blur must be finite and >= 0 degrees");
  for (std::size_t i = 0; i < stops_.size(); ++i) {
    const auto& s = stops_[i];
    require(std::isfinite(s.angle) && s.angle >= 0.0 && s.angle <= 90.0,
            "stop angles must be in [0, 90] degrees, got " + std::to_string(s.angle));
    checkColor(s.color, "stop colours");
    if (i > 0) require(s.angle > stops_[i - 1].angle, "stop angles must increase strictly");
  }
  // g on the whole line: mirrored about 0, constant beyond the last stop.
  auto addLinear = [&](double a, double b, const Rgb& ya, const Rgb& yb) {
    const Rgb beta = (yb - ya) / (b - a);
    pieces_.push_back({a, b, ya - beta * a, beta});
    pieces_.push_back({-b, -a, ya - beta * a, -beta});  // mirror: g(t) = g(-t)
  };
  const auto& first = stops_.front();
  const auto& last = stops_.back();
  pieces_.push_back({-first.angle, first.angle, first.color, Rgb::Zero()});
  for (std::size_t i = 0; i + 1 < stops_.size(); ++i) {
    addLinear(stops_[i].angle, stops_[i + 1].angle, stops_[i].color, stops_[i + 1].color);
  }
  pieces_.push_back({last.angle, kInf, last.color, Rgb::Zero()});
  pieces_.push_back({-kInf, -last.angle, last.color, Rgb::Zero()});
}

Rgb ColorGradient::sharp(double theta) const {
  const double t = std::abs(theta);
  if (t <= stops_.front().angle) return stops_.front().color;
  for (std::size_t i = 0; i + 1 < stops_.size(); ++i) {
    const auto& a = stops_[i];
    const auto& b = stops_[i + 1];
    if (t <= b.angle) return a.color + (b.color - a.color) * ((t - a.angle) / (b.angle - a.angle));
  }
  return stops_.back().color;
}

Rgb ColorGradient::operator()(double theta) const {
  if (!(blur_ > 0.0)) return sharp(theta);
  // Integral of (alpha + beta t) N(t; theta, blur) over [a, b], per piece (u = (t - theta) / blur):
  // (alpha + beta theta) (Phi(ub) - Phi(ua)) + beta blur (phi(ua) - phi(ub)).
  Rgb sum = Rgb::Zero();
  for (const auto& p : pieces_) {
    const double ua = (p.a - theta) / blur_, ub = (p.b - theta) / blur_;
    if (ua > 9.0 || ub < -9.0) continue;  // Gaussian mass and density there are below 1e-18
    const double mass = normalCdf(ub) - normalCdf(ua);
    sum += (p.alpha + p.beta * theta) * mass + p.beta * (blur_ * (normalPdf(ua) - normalPdf(ub)));
  }
  return sum.max(0.0);
}

// ---- colorgram ----------------------------------------------------------------------------------

ColorgramBlend parseColorgramBlend(std::string_view name) {
  return parseByName(name, std::array{ColorgramBlend::Replace, ColorgramBlend::Modulate, ColorgramBlend::Add}, "blend");
}

std::string_view toString(ColorgramBlend blend) {
  switch (blend) {
    case ColorgramBlend::Replace:
      return "replace";
    case ColorgramBlend::Modulate:
      return "modulate";
    case ColorgramBlend::Add:
      return "add";
  }
  return "?";
}

ColorgramMaterial::ColorgramMaterial(ColorGradient gradient, double twistDegrees, ColorgramBlend blend)
    : gradient_(std::move(gradient)), twist_(twistDegrees), blend_(blend) {
  require(std::isfinite(twist_) && std::abs(twist_) <= 90.0, "twist must be in [-90, 90] degrees");
}

std::optional<Rgb> ColorgramMaterial::neutralColor(ColorgramBlend blend) {
  switch (blend) {
    case ColorgramBlend::Modulate:
      return Rgb::Ones();
    case ColorgramBlend::Add:
      return Rgb::Zero();
    case ColorgramBlend::Replace:
      break;
  }
  return std::nullopt;
}

Rgb ColorgramMaterial::unlit(const ShadingGeometry& g) const {
  const double theta = viewAngleDegrees(g.normal.dot(g.view));
  const double across = twist_ != 0.0 ? g.normal.dot(viewFrame(g.view).right) : 0.0;
  return gradient_(theta - twist_ * across);
}

std::vector<Vec2> fleckOffsets(std::size_t count, double radius, std::uint64_t seed) {
  require(std::isfinite(radius) && radius >= 0.0 && radius <= 0.5, "fleck offset radius must be in [0, 0.5]");
  // SplitMix64 (Steele, Lea & Flood 2014): fixed, portable.
  std::uint64_t state = seed;
  auto next = [&state] {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  auto uniform = [&next] { return static_cast<double>(next() >> 11) * 0x1.0p-53; };  // [0, 1)
  std::vector<Vec2> offsets;
  offsets.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double r = radius * std::sqrt(uniform());
    const double phi = kTwoPi * uniform();
    offsets.emplace_back(r * std::cos(phi), r * std::sin(phi));
  }
  return offsets;
}

// ---- Gooch --------------------------------------------------------------------------------------

GoochMaterial::GoochMaterial(GoochParams params) : params_(std::move(params)) {
  checkColor(params_.cool, "cool");
  checkColor(params_.warm, "warm");
  checkColor(params_.highlight, "highlight colour");
  require(std::isfinite(params_.highlightSize) && params_.highlightSize >= 0.0 && params_.highlightSize <= 180.0,
          "highlight size must be in [0, 180] degrees");
  require(std::isfinite(params_.blur) && params_.blur >= 0.0 && params_.blur <= 180.0,
          "blur must be in [0, 180] degrees");
  const double norm = params_.lightDirection.norm();
  require(std::isfinite(norm) && norm > 0.0, "light direction must be a finite non-zero vector");
  params_.lightDirection /= norm;
}

Rgb GoochMaterial::unlit(const ShadingGeometry& g) const {
  const Vec3& l = params_.lightDirection;
  const double psi = degrees(std::asin(clampFinite(g.normal.dot(l), -1.0, 1.0)));
  const double t = softStep(psi, params_.blur);
  const Rgb base = (1.0 - t) * params_.cool + t * params_.warm;
  if (!(params_.highlightSize > 0.0)) return base;
  const Vec3 sum = l + g.view;
  if (!(sum.norm() > 1e-12)) return base;
  const Vec3 h = sum.normalized();
  const double angle = degrees(std::acos(clampFinite(g.normal.dot(h), -1.0, 1.0)));
  const double w = softStep(params_.highlightSize - angle, params_.blur);
  return (1.0 - w) * base + w * params_.highlight;
}

// ---- silhouette ---------------------------------------------------------------------------------

SilhouetteMaterial::SilhouetteMaterial(double widthDegrees, const Rgb& color, const Rgb& background)
    : width_(widthDegrees), color_(color), background_(background) {
  require(std::isfinite(width_) && width_ > 0.0 && width_ <= 90.0, "ring width must be in (0, 90] degrees");
  checkColor(color_, "ring colour");
  checkColor(background_, "background colour");
  sinWidth_ = std::sin(radians(width_));
}

Rgb SilhouetteMaterial::unlit(const ShadingGeometry& g) const {
  return g.normal.dot(g.view) < sinWidth_ ? color_ : background_;
}

double SilhouetteMaterial::ringTexels(int resolution) const {
  return (1.0 - std::cos(radians(width_))) * resolution / 2.0;
}

SilhouetteMaterial SilhouetteMaterial::forMipLevel(int baseResolution, int levelResolution) const {
  require(baseResolution >= 1 && levelResolution >= 1, "resolutions must be >= 1");
  const double inner = 1.0 - (1.0 - std::cos(radians(width_))) * baseResolution / levelResolution;
  const double width = inner > 0.0 ? degrees(std::acos(inner)) : 90.0;
  return SilhouetteMaterial(std::clamp(width, width_, 90.0), color_, background_);
}

// ---- hatching -----------------------------------------------------------------------------------

HatchingMaterial::HatchingMaterial(HatchingParams params) : params_(std::move(params)) {
  const auto& p = params_;
  require(std::isfinite(p.width) && p.width > 0.0 && p.width <= 90.0, "hatching width must be in (0, 90] degrees");
  require(std::isfinite(p.spacing) && p.spacing > 0.0 && p.spacing <= 2.0, "stroke spacing must be in (0, 2]");
  require(std::isfinite(p.angle), "stroke angle must be finite");
  checkColor(p.ink, "ink");
  checkColor(p.paper, "paper");
}

double HatchingMaterial::coverage(double theta) const {
  return std::clamp((theta - (90.0 - params_.width)) / params_.width, 0.0, 1.0);
}

Rgb HatchingMaterial::unlit(const ShadingGeometry& g) const {
  const double q = coverage(viewAngleDegrees(g.normal.dot(g.view)));
  if (!(q > 0.0)) return params_.paper;
  const ViewFrame frame = viewFrame(g.view);
  const double x = g.normal.dot(frame.right), y = g.normal.dot(frame.up);
  const double a = radians(params_.angle);
  const double u1 = (x * std::cos(a) + y * std::sin(a)) / params_.spacing;
  const double u2 = (-x * std::sin(a) + y * std::cos(a)) / params_.spacing;
  const bool stroke1 = std::abs(fraction(u1) - 0.5) < 0.5 * q;
  const bool stroke2 = std::abs(fraction(u2) - 0.5) < 0.5 * (2.0 * q - 1.0);
  return stroke1 || stroke2 ? params_.ink : params_.paper;
}

}  // namespace brdfbake
