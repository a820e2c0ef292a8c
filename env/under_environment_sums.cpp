// The integrals of a material over an environment (under_environment_internal.hpp): the split into
// bright texels and the rest, the bright texels as lights, filtered importance sampling of the BRDF's
// reflection lobes, the reference sum, and the polar grid of normals.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "under_environment_internal.hpp"

namespace brdfbake::detail {
namespace {

// Radical inverse in base 2 (Hammersley points), XOR-scrambled by `scramble`.
double radicalInverse(unsigned i, unsigned scramble) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return static_cast<double>(i ^ scramble) * 2.3283064365386963e-10;
}

// The reference's texels per local scale of the integrand: against a brute-force sum over every
// texel of a 512 x 256 sky, 4 is within 0.02 % of the peak (RMS) for GGX 0.02 ... 0.3 and Phong 50
// ... 10000 (2 was within 0.07 %, 8 within 0.04 % at three times the cost; docs/matcap.md).
constexpr double kPerScale = 4.0;

double rowLuminance(const Image& image, int x, int y) { return luminance(image.at(x, y).head<3>()); }

// Angle (radians) between two unit vectors, accurate for small angles.
double angleBetween(const Vec3& a, const Vec3& b) { return 2.0 * std::asin(std::min(1.0, 0.5 * (a - b).norm())); }

}  // namespace

// ---- the split -------------------------------------------------------------------------------

EnvironmentSplit splitEnvironment(const Environment& environment, double factor, int maxTexels) {
  const Parameterization& map = *environment.map;
  const Image& image = environment.image;
  double sum = 0.0, weight = 0.0;
  std::vector<double> values;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const double omega = map.texelSolidAngle(x, y);
      if (!(omega > 0.0)) continue;
      const double value = rowLuminance(image, x, y);
      sum += omega * value, weight += omega;
      values.push_back(value);
    }
  EnvironmentSplit split;
  split.rest = environment;
  const double mean = weight > 0.0 ? sum / weight : 0.0;
  double threshold = factor * mean;
  if (static_cast<int>(values.size()) > maxTexels && maxTexels >= 0) {
    // Raise the threshold to the (maxTexels + 1)-th largest value, so that at most maxTexels exceed it.
    std::nth_element(values.begin(), values.begin() + maxTexels, values.end(), std::greater<>());
    threshold = std::max(threshold, values[static_cast<std::size_t>(maxTexels)]);
  }
  split.threshold = threshold;
  if (!(mean > 0.0)) return split;
  double bright = 0.0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const double omega = map.texelSolidAngle(x, y);
      const double value = rowLuminance(image, x, y);
      if (!(omega > 0.0) || !(value > threshold)) continue;
      const Rgba texel = image.at(x, y);
      const double keep = threshold / value;
      BrightTexel t;
      t.direction = *map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      t.power = texel.head<3>() * (1.0 - keep) * omega;
      t.angle = std::sqrt(omega * map.anisotropy(Vec2(x + 0.5, y + 0.5)));  // the long side
      t.x = x, t.y = y;
      split.texels.push_back(t);
      bright += (value - threshold) * omega;
      Rgba clipped = texel;
      clipped.head<3>() *= keep;
      split.rest.image.set(x, y, clipped);
    }
  split.brightShare = bright / sum;
  return split;
}

int subdivisionFor(double angle, double width, double perWidth, int limit) {
  if (!(width > 0.0)) return limit;
  return std::clamp(static_cast<int>(std::ceil(angle * perWidth / width)), 1, limit);
}

// ---- bright texels as lights -----------------------------------------------------------------

LightSet::LightSet(const Environment& input, const std::vector<BrightTexel>& texels, const Mat3& environmentToEye,
                   int sub) {
  const Parameterization& map = *input.map;
  for (const BrightTexel& t : texels) {
    const Rgb part = t.power / static_cast<double>(sub * sub);
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const auto d = map.getDirectionFor(Vec2(t.x + (b + 0.5) / sub, t.y + (a + 0.5) / sub));
        directions_.push_back(environmentToEye * (d ? *d : t.direction));
        powers_.push_back(part);
      }
  }
}

Rgb LightSet::sum(const Material& material, const ShadingGeometry& g) const {
  Rgb total = Rgb::Zero();
  for (std::size_t i = 0; i < directions_.size(); ++i) total += material.shade(g, directions_[i]) * powers_[i];
  return total;
}

// ---- filtered importance sampling ------------------------------------------------------------

LobeSampler::LobeSampler(const LatLongPyramid& rest, const Mat3& eyeToEnvironment, int samples)
    : rest_(rest), eyeToEnvironment_(eyeToEnvironment), samples_(samples) {
  const LatLongLevel& base = rest.level(0);
  equatorTexel_ = (kPi / base.height) * (kTwoPi / base.width);
}

Rgb LobeSampler::integrate(const Material& material, const ShadingGeometry& g,
                           const std::vector<ReflectionLobe>& lobes) const {
  const int count = static_cast<int>(lobes.size());
  double total = 0.0;
  for (const auto& lobe : lobes) total += lobe.weight;
  // Each lobe's share of the samples by weight, at least a quarter of an even split.
  std::vector<int> share(lobes.size());
  for (int c = 0; c < count; ++c) {
    const double fraction = total > 0.0 ? lobes[c].weight / total : 1.0 / count;
    share[c] = std::max(static_cast<int>(std::lround(samples_ * fraction)), std::max(1, samples_ / (4 * count)));
  }
  Rgb sum = Rgb::Zero();
  for (int c = 0; c < count; ++c) {
    const unsigned scramble = 0x9E3779B9u * static_cast<unsigned>(c);
    for (int i = 0; i < share[c]; ++i) {
      const auto l = sampleReflectionLobe(lobes[c], g.view, (i + 0.5) / share[c], radicalInverse(i, scramble));
      if (!l) continue;
      double density = 0.0;  // Σ_c K_c p_c(l): samples per steradian at l
      for (int k = 0; k < count; ++k) density += share[k] * reflectionLobeDensity(lobes[k], g.view, *l);
      if (!(density > 0.0)) continue;
      const Rgb f = material.shade(g, *l);
      if (!(f.abs().maxCoeff() > 0.0)) continue;
      const Vec3 d = eyeToEnvironment_ * *l;
      const double sinTheta = std::sqrt(std::max(0.0, 1.0 - d.y() * d.y()));
      // The level whose texels cover the sample's solid angle 1 / density. Křivánek & Colbert 2008 read one
      // level coarser, which hides noise but blurs the sky into the lobe: under the sample sky a GGX
      // alpha 0.09 matcap's dim texels came out up to 15 % high with 16 samples and 2.7 % with 256
      // (6 % and 1.2 % at this level).
      const double lod = 0.5 * std::log2(1.0 / (density * equatorTexel_ * std::max(sinTheta, 1e-9)));
      sum += f * rest_.trilinear(d.normalized(), lod) / density;
    }
  }
  return sum;
}

// ---- the reference ---------------------------------------------------------------------------

ReferenceSum::ReferenceSum(const Environment& input, const EnvironmentSplit& split, const LatLongPyramid& rest,
                           const Mat3& eyeToEnvironment)
    : input_(input),
      split_(split),
      rest_(rest),
      eyeToEnvironment_(eyeToEnvironment),
      environmentToEye_(eyeToEnvironment.transpose()) {
  startLevel_ = 0;
  while (startLevel_ + 1 < rest.levels() && rest.level(startLevel_ + 1).height >= 16) ++startLevel_;
}

Rgb ReferenceSum::value(const Material& material, const ShadingGeometry& g) const {
  const auto lobes = material.reflectionLobes(g);
  require(lobes.has_value(), "the reference needs a material with a BRDF");
  std::vector<ReflectionLobe> narrow;
  std::vector<Vec3> peaks;  // environment frame
  double narrowest = 1.0;
  for (const auto& lobe : *lobes) {
    if (lobe.shape == ReflectionLobeShape::Cosine) continue;
    narrow.push_back(lobe);
    peaks.push_back(eyeToEnvironment_ * reflectionLobePeak(lobe, g.view));
    narrowest = std::min(narrowest, reflectionLobeWidth(lobe));
  }
  Rgb sum = Rgb::Zero();
  const Parameterization& map = *input_.map;
  for (const BrightTexel& t : split_.texels) {
    const int sub = subdivisionFor(t.angle, narrowest, 2.0 * kPerScale, 16);
    const Rgb part = t.power / static_cast<double>(sub * sub);
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const auto d = map.getDirectionFor(Vec2(t.x + (b + 0.5) / sub, t.y + (a + 0.5) / sub));
        sum += material.shade(g, environmentToEye_ * (d ? *d : t.direction)) * part;
      }
  }
  const LatLongLevel& start = rest_.level(startLevel_);
  for (int y = 0; y < start.height; ++y)
    for (int x = 0; x < start.width; ++x) visit(material, g, narrow, peaks, startLevel_, x, y, sum);
  return sum;
}

void ReferenceSum::visit(const Material& material, const ShadingGeometry& g, const std::vector<ReflectionLobe>& lobes,
                         const std::vector<Vec3>& peaks, int level, int x, int y, Rgb& sum) const {
  const LatLongLevel& L = rest_.level(level);
  const Vec3 centre(L.rowSin[y] * L.columnSin[x], L.rowCos[y], -L.rowSin[y] * L.columnCos[x]);
  const double size = kPi / L.height;  // the texel's extent in theta (its extent in phi is no larger)
  const double radius = 0.75 * size;
  // The local scale of the integrand over the texel.
  double scale = 1.0;
  for (std::size_t k = 0; k < lobes.size(); ++k) {
    const double d = std::max(0.0, angleBetween(centre, peaks[k]) - radius);
    scale = std::min(scale, std::max(reflectionLobeWidth(lobes[k]), d / 3.0));
  }
  const Vec3 eye = environmentToEye_ * centre;
  if (std::abs(g.normal.dot(eye)) < std::sin(radius)) scale = std::min(scale, radians(8.0));  // down to 1 degree
  if (size <= scale / kPerScale) {
    sum += material.shade(g, eye) * L.at(x, y) * L.rowSolidAngle[y];
    return;
  }
  if (level == 0) {
    sumLevelZero(material, g, x, y, subdivisionFor(size, scale, kPerScale, 16), sum);
    return;
  }
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) visit(material, g, lobes, peaks, level - 1, 2 * x + b, 2 * y + a, sum);
}

void ReferenceSum::sumLevelZero(const Material& material, const ShadingGeometry& g, int x, int y, int sub,
                                Rgb& sum) const {
  const LatLongLevel& L = rest_.level(0);
  const Rgb radiance = L.at(x, y);
  const double theta0 = kPi * y / L.height, dTheta = kPi / L.height / sub;
  const double phi0 = kTwoPi * x / L.width - kPi, dPhi = kTwoPi / L.width / sub;
  Rgb texel = Rgb::Zero();
  for (int a = 0; a < sub; ++a) {
    const double t0 = theta0 + a * dTheta, t1 = t0 + dTheta, t = t0 + 0.5 * dTheta;
    const double omega = dPhi * (std::cos(t0) - std::cos(t1));  // exact solid angle of the sub-texel
    for (int b = 0; b < sub; ++b) {
      const double p = phi0 + (b + 0.5) * dPhi;
      const Vec3 d(std::sin(t) * std::sin(p), std::cos(t), -std::sin(t) * std::cos(p));
      texel += material.shade(g, environmentToEye_ * d) * omega;
    }
  }
  sum += texel * radiance;
}

// ---- the polar grid of normals ---------------------------------------------------------------

NormalGrid::NormalGrid(const Vec3& view, int rows, int columns)
    : v_(view.normalized()), rows_(rows), columns_(columns), values_(static_cast<std::size_t>(rows) * columns) {
  require(rows >= 2 && columns >= 4, "normal grid: at least 2 rows and 4 columns");
  t_ = anyPerpendicular(v_);
  b_ = v_.cross(t_);
  dTheta_ = 0.5 * kPi / (rows_ - 1);
  dPhi_ = kTwoPi / columns_;
}

Vec3 NormalGrid::normal(int row, int column) const {
  const double theta = row * dTheta_, phi = column * dPhi_;
  return (std::sin(theta) * (std::cos(phi) * t_ + std::sin(phi) * b_) + std::cos(theta) * v_).normalized();
}

void NormalGrid::angles(const Vec3& normal, double& theta, double& phi) const {
  const double x = normal.dot(t_), y = normal.dot(b_), z = normal.dot(v_);
  theta = std::atan2(std::hypot(x, y), z);
  phi = std::atan2(y, x);
  if (phi < 0.0) phi += kTwoPi;
}

void NormalGrid::finish() {
  paddedColumns_ = columns_ + 3;
  padded_.assign(static_cast<std::size_t>(rows_ + 3) * paddedColumns_, Rgb::Zero());
  auto wrapped = [&](int c) { return ((c % columns_) + columns_) % columns_; };
  for (int row = -1; row <= rows_ + 1; ++row)
    for (int column = -1; column <= columns_ + 1; ++column) {
      Rgb value;
      if (row < 0) {  // across the pole: row -1 is row 1 at phi + pi
        value = values_[index(1, wrapped(column + columns_ / 2))];
      } else if (row < rows_) {
        value = values_[index(row, wrapped(column))];
      } else {  // beyond the rim (n.v < 0, where no normal is seen): continued linearly
        const int last = rows_ - 1, beyond = row - last;
        value = values_[index(last, wrapped(column))] * (1.0 + beyond) -
                values_[index(last - 1, wrapped(column))] * static_cast<double>(beyond);
      }
      padded_[static_cast<std::size_t>(row + 1) * paddedColumns_ + (column + 1)] = value;
    }
}

Rgb NormalGrid::value(const Vec3& normal) const {
  double theta = 0.0, phi = 0.0;
  angles(normal, theta, phi);
  const double py = std::min(theta, 0.5 * kPi) / dTheta_, px = phi / dPhi_;
  const int iy = std::min(static_cast<int>(py), rows_ - 1), ix = std::min(static_cast<int>(px), columns_ - 1);
  const double ty = py - iy, tx = px - ix;
  const std::array<double, 4> wx = catmullRomWeights(tx), wy = catmullRomWeights(ty);
  Rgb sum = Rgb::Zero();
  for (int j = 0; j < 4; ++j) {
    // Padded row iy - 1 + j is table row iy + j; padded column ix - 1 is table column ix.
    const Rgb* row = padded_.data() + static_cast<std::size_t>(iy + j) * paddedColumns_ + ix;
    sum += wy[j] * (wx[0] * row[0] + wx[1] * row[1] + wx[2] * row[2] + wx[3] * row[3]);
  }
  return sum;
}

}  // namespace brdfbake::detail
