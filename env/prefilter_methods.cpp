// The prefilter methods at one axis: working pyramid, direct sums, filtered importance sampling,
// spherical harmonics, interpolation grid, and the exact reference.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <bit>

#include "prefilter_internal.hpp"

namespace brdfbake::detail {
namespace {

// The Euclidean norm of an RGB value: how the error estimates weigh colours.
double rgbNorm(const Rgb& v) { return v.matrix().norm(); }

// Radical inverse in base 2 (Hammersley points).
double radicalInverse(unsigned i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return static_cast<double>(i) * 2.3283064365386963e-10;
}

// An orthonormal frame with `axis` as its third vector.
void frame(const Vec3& axis, Vec3& t, Vec3& b) {
  t = anyPerpendicular(axis);
  b = axis.cross(t);
}

}  // namespace

// ---- lat-long levels -------------------------------------------------------------------------

LatLongLevel::LatLongLevel(Image levelImage)
    : map(levelImage.height()), image(std::move(levelImage)), height(map.height()), width(map.width()) {
  require(image.width() == width && image.height() == height, "working lat-long: image is not 2N x N");
  // Tables from the map's directions: at phi = 0 (pixel x = H) a direction is (0, cos theta, -sin theta),
  // on the equator (pixel y = H/2) it is (sin phi, 0, -cos phi).
  auto at = [&](double px, double py) { return *map.getDirectionFor(Vec2(px, py)); };
  rowCos.resize(height), rowSin.resize(height), rowSolidAngle.resize(height);
  edgeCos.resize(height + 1), edgeSin.resize(height + 1);
  for (int y = 0; y <= height; ++y) {
    const Vec3 d = at(height, y);
    edgeCos[y] = d.y(), edgeSin[y] = -d.z();
  }
  for (int y = 0; y < height; ++y) {
    const Vec3 d = at(height, y + 0.5);
    rowCos[y] = d.y(), rowSin[y] = -d.z();
    rowSolidAngle[y] = map.texelSolidAngle(0, y);
  }
  columnCos.resize(width), columnSin.resize(width);
  for (int x = 0; x < width; ++x) {
    const Vec3 d = at(x + 0.5, 0.5 * height);
    columnCos[x] = -d.z(), columnSin[x] = d.x();
  }
}

namespace {

// Level 0 of the working lat-long: the input itself when it is a power-of-two lat-long image, else
// the input resampled at enough rows to keep its finest texels (sphere texels ~4/N rad,
// paraboloid rim and cube texels ~1/N ... 2/N rad), each texel the mean of 2 x 2 bilinear lookups.
Image workingLatLong(const Environment& environment, bool& resampled) {
  const Parameterization& map = *environment.map;
  resampled =
      !(map.kind() == ParameterizationKind::LatLong && std::has_single_bit(static_cast<unsigned>(map.resolution())));
  if (!resampled) return environment.image;
  const double factor = map.kind() == ParameterizationKind::Sphere    ? 0.8
                        : map.kind() == ParameterizationKind::LatLong ? 1.0
                                                                      : 1.6;
  const int rows = std::min(
      4096,
      static_cast<int>(std::bit_ceil(static_cast<unsigned>(std::max(8.0, std::ceil(factor * map.resolution()))))));
  const LatLongMap base(rows);
  Image image(base.width(), base.height(), Rgba(0, 0, 0, 1));
  tbb::parallel_for(0, base.height(), [&](int y) {
    for (int x = 0; x < base.width(); ++x) {
      Rgb value = Rgb::Zero();
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          value += environment.radiance(*base.getDirectionFor(Vec2(x + 0.25 + 0.5 * b, y + 0.25 + 0.5 * a)));
      value *= 0.25;
      image.set(x, y, Rgba(value[0], value[1], value[2], 1.0));
    }
  });
  return image;
}

}  // namespace

LatLongPyramid::LatLongPyramid(const Environment& environment) {
  levels_.reserve(16);
  levels_.emplace_back(workingLatLong(environment, resampled_));
  // The solid-angle mip chain (as environmentMipChain makes it; lat-long levels need no fixup).
  while (levels_.back().height > 1)
    levels_.emplace_back(downsampleEnvironment(levels_.back().image, levels_.back().map));
  const LatLongLevel& L = levels_.front();
  double normSum = 0.0;
  for (int y = 0; y < L.height; ++y)
    for (int x = 0; x < L.width; ++x) normSum += L.rowSolidAngle[y] * rgbNorm(L.at(x, y));
  meanNorm_ = normSum / kFourPi;
}

int LatLongPyramid::levelFor(double angle) const {
  int best = 0;
  for (int l = 0; l < levels(); ++l)
    if (texelAngle(l) <= angle) best = l;
  return best;
}

Rgb LatLongPyramid::trilinear(const Vec3& direction, double lod) const {  // direction: unit
  lod = std::clamp(lod, 0.0, static_cast<double>(levels() - 1));
  const int l0 = static_cast<int>(lod);
  const double f = lod - l0;
  // Lat-long pixel coordinates are linear in (phi, theta): address once, scale to each level.
  const Vec2 pixel = levels_[0].map.pixelForUnit(direction) / levels_[0].height;
  const Rgb a = levels_[l0].bilinear(Vec2(pixel * levels_[l0].height));
  if (f <= 0.0 || l0 + 1 >= levels()) return a;
  return (1.0 - f) * a + f * levels_[l0 + 1].bilinear(Vec2(pixel * levels_[l0 + 1].height));
}

// ---- direct sum over the lobe's support ------------------------------------------------------

double capRowHalfWidth(const LatLongLevel& level, int y, double cosD, double sinD, double cosCap) {
  if (cosCap <= -1.0 || sinD <= 1e-12) return kPi;
  // A point at polar angle theta and azimuth offset dphi lies in the cap where cos theta cosD +
  // sin theta sinD cos dphi >= cosCap, i.e. cos dphi >= kappa(theta) = (cosCap - cos theta cosD) /
  // (sin theta sinD). The widest offset over the band is acos of kappa's least value on it: at an
  // edge, or where d kappa / d theta = 0 (cos theta = cosD / cosCap, for cosCap > 0) inside the band.
  auto kappa = [&](double cosT, double sinT) {
    if (sinT < 1e-12) return cosT * cosD >= cosCap ? -2.0 : 2.0;  // a pole: all of the row's parallel or none
    return (cosCap - cosT * cosD) / (sinT * sinD);
  };
  double k = std::min(kappa(level.edgeCos[y], level.edgeSin[y]), kappa(level.edgeCos[y + 1], level.edgeSin[y + 1]));
  if (cosCap > 0.0) {
    const double cosWidest = cosD / cosCap;  // edges: cos decreasing with y
    if (cosWidest < level.edgeCos[y] && cosWidest > level.edgeCos[y + 1]) {
      k = std::min(k, kappa(cosWidest, std::sqrt(std::max(0.0, 1.0 - cosWidest * cosWidest))));
    }
  }
  if (k > 1.0) return -1.0;
  return k <= -1.0 ? kPi : std::acos(k);
}

DirectSummer::DirectSummer(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int level, double cosCap, int sub,
                           std::shared_ptr<const RadialTable> table)
    : pyramid_(pyramid),
      lobe_(lobe),
      level_(level),
      sub_(sub),
      cosCap_(cosCap),
      capAngle_(std::acos(std::clamp(cosCap, -1.0, 1.0))),
      table_(std::move(table)) {
  if (sub_ > 1) {
    const LatLongLevel& L = pyramid_.level(level_);
    const double dPhi = kTwoPi / L.width;
    subColumnCos_.resize(static_cast<std::size_t>(L.width) * sub_), subColumnSin_.resize(subColumnCos_.size());
    for (int x = 0; x < L.width; ++x)
      for (int b = 0; b < sub_; ++b) {
        const double phi = (x + (b + 0.5) / sub_) * dPhi - kPi;
        subColumnCos_[x * sub_ + b] = std::cos(phi), subColumnSin_[x * sub_ + b] = std::sin(phi);
      }
  }
}

double DirectSummer::texelsPerAxis() const {
  const LatLongLevel& L = pyramid_.level(level_);
  const double capSolidAngle = kTwoPi * (1.0 - cosCap_);
  const double meanTexel = kFourPi / (static_cast<double>(L.width) * L.height);
  // Rows near the poles hold more texels per steradian; the band of rows and the column margin add more.
  const double texels = 1.4 * capSolidAngle / meanTexel + 2.0 * (2.0 * capAngle_ / kPi * L.height + 1.0) + 4.0;
  return std::min(texels, static_cast<double>(L.width) * L.height) * sub_ * sub_;
}

void DirectSummer::sum(const Vec3& axis, Rgb& numerator, double& denominator) const {
  const LatLongLevel& L = pyramid_.level(level_);
  // The axis in the map's coordinates: theta from the row coordinate, phi's cosine and sine from
  // the direction on the equator of the axis's column.
  const Vec2 pixel = L.map.getAddressFor(axis).pixel;
  const double thetaD = pixel.y() * kPi / L.height;
  const double cosD = std::cos(thetaD), sinD = std::sin(thetaD);
  const Vec3 equator = *L.map.getDirectionFor(Vec2(pixel.x(), 0.5 * L.height));
  const double cosPhiD = -equator.z(), sinPhiD = equator.x();
  const double dTheta = kPi / L.height, dPhi = kTwoPi / L.width;
  const int yFirst = std::max(0, static_cast<int>(std::floor((thetaD - capAngle_) / dTheta)));
  const int yLast = std::min(L.height - 1, static_cast<int>(std::floor((thetaD + capAngle_) / dTheta)));
  const bool exact = !table_;
  const RadialTable::View view = exact ? RadialTable::View{nullptr, 0.0, 0} : table_->view();
  double nr = 0.0, ng = 0.0, nb = 0.0, den = 0.0;
  const double u0 = pixel.x() - 0.5;  // column coordinate of the axis (centres at integers)
  // The weight of a sample at cosine c to the axis.
  auto weight = [&](double c) {
    if (exact) return lobe_.weight(c);
    return view(std::sqrt(std::max(0.0, 0.5 - 0.5 * c)));  // the table is over u = sin(theta/2)
  };
  for (int y = yFirst; y <= yLast; ++y) {
    const double halfWidth = capRowHalfWidth(L, y, cosD, sinD, cosCap_);
    if (halfWidth < 0.0) continue;
    int xFirst = 0, count = L.width;
    if (halfWidth < kPi - 2.0 * dPhi) {
      xFirst = static_cast<int>(std::floor(u0 - halfWidth / dPhi)) - 1;
      count = std::min(L.width, static_cast<int>(std::ceil(u0 + halfWidth / dPhi)) + 2 - xFirst);
      xFirst = ((xFirst % L.width) + L.width) % L.width;
    }
    // The columns as at most two contiguous runs.
    const int firstEnd = std::min(L.width, xFirst + count);
    const int runs[2][2] = {{xFirst, firstEnd}, {0, xFirst + count - firstEnd}};
    const float* row = L.row(y);
    if (sub_ == 1) {
      const double a = L.rowCos[y] * cosD, b = L.rowSin[y] * sinD, omega = L.rowSolidAngle[y];
      const double bc = b * cosPhiD, bs = b * sinPhiD;
      const double* cc = L.columnCos.data();
      const double* cs = L.columnSin.data();
      double rr = 0.0, rg = 0.0, rb = 0.0, rw = 0.0;
      for (const auto& run : runs) {
        for (int x = run[0]; x < run[1]; ++x) {
          const double w = weight(a + cc[x] * bc + cs[x] * bs);
          const float* p = row + 4 * x;
          rr += w * p[0], rg += w * p[1], rb += w * p[2], rw += w;
        }
      }
      nr += omega * rr, ng += omega * rg, nb += omega * rb, den += omega * rw;
    } else {
      for (int sa = 0; sa < sub_; ++sa) {
        const double t0 = y * dTheta + sa * dTheta / sub_, t1 = t0 + dTheta / sub_, tc = 0.5 * (t0 + t1);
        const double a = std::cos(tc) * cosD, b = std::sin(tc) * sinD;
        const double bc = b * cosPhiD, bs = b * sinPhiD;
        const double omega = dPhi / sub_ * (std::cos(t0) - std::cos(t1));
        for (const auto& run : runs) {
          for (int x = run[0]; x < run[1]; ++x) {
            const float* p = row + 4 * x;
            double wx = 0.0;
            for (int sb = 0; sb < sub_; ++sb) {
              const std::size_t k = static_cast<std::size_t>(x) * sub_ + sb;
              wx += weight(a + subColumnCos_[k] * bc + subColumnSin_[k] * bs);
            }
            wx *= omega;
            nr += wx * p[0], ng += wx * p[1], nb += wx * p[2], den += wx;
          }
        }
      }
    }
  }
  numerator = Rgb(nr, ng, nb);
  denominator = den;
}

Rgb DirectSummer::value(const Vec3& axis) const {
  Rgb numerator;
  double denominator;
  sum(axis, numerator, denominator);
  if (denominator > 0.0) return lobe_.mass() * numerator / denominator;
  // The lobe fell between samples: its limit is the value at the axis.
  return lobe_.mass() * pyramid_.level(level_).bilinear(axis);
}

// ---- the direct sum on a grid, by row convolutions ----------------------------------------------

LatLongGrid convolvedDirectGrid(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int level, double cosCap,
                                const std::shared_ptr<const RadialTable>& table, int multiple) {
  const LatLongLevel& L = pyramid.level(level);
  const int ws = L.width, hs = L.height, m = multiple;
  LatLongGrid grid(hs * m);
  const double dTheta = kPi / hs, dPhi = kTwoPi / ws, capAngle = std::acos(std::clamp(cosCap, -1.0, 1.0));
  const double gTheta = kPi / grid.height();
  // Each source row's channels, planar, twice over and shifted by half a row: source column j + k
  // (j in [0, ws), |k| <= ws / 2) at [j + k + ws / 2] without wrapping.
  const int half = ws / 2;
  std::vector<float> planar(static_cast<std::size_t>(hs) * 3 * 2 * ws);
  for (int y = 0; y < hs; ++y)
    for (int ch = 0; ch < 3; ++ch) {
      float* dst = planar.data() + (static_cast<std::size_t>(y) * 3 + ch) * 2 * ws;
      const float* row = L.row(y);
      for (int i = 0; i < 2 * ws; ++i) dst[i] = row[4 * ((i - half + ws) % ws) + ch];
    }
  // cos((k - f_p) dPhi) for phase p (f_p = (p + 0.5) / m - 0.5, the grid column's offset within its
  // source column) and k in [-ws/2, ws/2].
  std::vector<double> cosOffset(static_cast<std::size_t>(m) * (ws + 1));
  for (int p = 0; p < m; ++p)
    for (int k = -half; k <= half; ++k)
      cosOffset[static_cast<std::size_t>(p) * (ws + 1) + (k + half)] = std::cos((k - ((p + 0.5) / m - 0.5)) * dPhi);
  const RadialTable::View view = table->view();
  auto weight = [&](double c) { return view(std::sqrt(std::max(0.0, 0.5 - 0.5 * c))); };  // over u = sin(theta/2)
  const double mass = lobe.mass();
  tbb::parallel_for(0, grid.height(), [&](int gy) {
    const double thetaD = (gy + 0.5) * gTheta, cosD = std::cos(thetaD), sinD = std::sin(thetaD);
    std::vector<float> acc(static_cast<std::size_t>(m) * 3 * ws, 0.0f);
    std::vector<double> den(static_cast<std::size_t>(m), 0.0);
    std::vector<float> kernel(static_cast<std::size_t>(ws) + 1);
    const int yFirst = std::max(0, static_cast<int>(std::floor((thetaD - capAngle) / dTheta)));
    const int yLast = std::min(hs - 1, static_cast<int>(std::floor((thetaD + capAngle) / dTheta)));
    for (int y = yFirst; y <= yLast; ++y) {
      const double halfWidth = capRowHalfWidth(L, y, cosD, sinD, cosCap);
      if (halfWidth < 0.0) continue;
      // Taps k in [kLo, kHi]: the whole row (each column once) or the cap's columns and a margin.
      int kLo = -half, kHi = ws - 1 - half;
      if (halfWidth < kPi - 2.0 * dPhi) {
        const int reach = std::min(half - 1, static_cast<int>(std::ceil(halfWidth / dPhi)) + 1);
        kLo = -reach, kHi = reach;
      }
      const double a = L.rowCos[y] * cosD, b = L.rowSin[y] * sinD, omega = L.rowSolidAngle[y];
      for (int p = 0; p < m; ++p) {
        const double* co = cosOffset.data() + static_cast<std::size_t>(p) * (ws + 1) + half;
        double sum = 0.0;
        for (int k = kLo; k <= kHi; ++k) {
          const double w = omega * weight(a + b * co[k]);
          kernel[k - kLo] = static_cast<float>(w);
          sum += w;
        }
        den[p] += sum;
        for (int ch = 0; ch < 3; ++ch) {
          float* __restrict out = acc.data() + (static_cast<std::size_t>(p) * 3 + ch) * ws;
          const float* source = planar.data() + (static_cast<std::size_t>(y) * 3 + ch) * 2 * ws + half;
          for (int k = kLo; k <= kHi; ++k) {
            const float w = kernel[k - kLo];
            if (w == 0.0f) continue;
            const float* __restrict in = source + k;
            for (int j = 0; j < ws; ++j) out[j] += w * in[j];
          }
        }
      }
    }
    for (int p = 0; p < m; ++p)
      for (int j = 0; j < ws; ++j) {
        const std::size_t base = static_cast<std::size_t>(p) * 3 * ws + j;
        const int x = j * m + p;
        if (den[p] > 0.0) {
          grid.set(x, gy, mass * Rgb(acc[base], acc[base + ws], acc[base + 2 * ws]) / den[p]);
        } else {
          grid.set(x, gy, mass * L.bilinear(grid.direction(x, gy)));
        }
      }
  });
  return grid;
}

// ---- filtered importance sampling ------------------------------------------------------------

ImportanceSampler::ImportanceSampler(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int samples)
    : pyramid_(pyramid), mass_(lobe.mass()) {
  const LatLongLevel& base = pyramid.level(0);
  const double equatorTexel = (kPi / base.height) * (kTwoPi / base.width);
  for (int i = 0; i < samples; ++i) {
    const double u = (i + 0.5) / samples, v = radicalInverse(static_cast<unsigned>(i));
    const double theta = lobe.sampleAngle(u), phi = kTwoPi * v;
    const double c = std::cos(theta), s = std::sin(theta);
    local_.emplace_back(s * std::cos(phi), s * std::sin(phi), c);
    const double pdf = lobe.weight(c) / mass_;
    // Solid angle of the sample 1/(K pdf); one level coarser (Křivánek's bias, log4 K = 1 in Filament).
    const double omega = pdf > 0.0 ? 1.0 / (samples * pdf) : kFourPi;
    lod_.push_back(0.5 * std::log2(omega / equatorTexel) + 1.0);
  }
}

Rgb ImportanceSampler::value(const Vec3& axis) const {
  Vec3 t, b;
  frame(axis, t, b);
  Rgb sum = Rgb::Zero();
  for (std::size_t i = 0; i < local_.size(); ++i) {
    const Vec3 d = local_[i].x() * t + local_[i].y() * b + local_[i].z() * axis;  // unit: an orthonormal frame
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - d.y() * d.y()));
    const double lod = lod_[i] - 0.5 * std::log2(std::max(sinTheta, 1e-9));
    sum += pyramid_.trilinear(d, lod);
  }
  return mass_ * sum / static_cast<double>(local_.size());
}

// ---- spherical harmonics ---------------------------------------------------------------------

ShFilter::ShFilter(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int order) {
  // Project the piecewise-constant level exactly: each texel's value times the integral of Y_lm
  // over the texel, which separates into an azimuth part (closed form) and a polar part (8-point
  // Gauss-Legendre per row), so constant and band-limited environments project without
  // quadrature error. The SH frame has its pole on the environment's +y (shFrame).
  projectionLevel_ = pyramid.levelFor(kPi / (8.0 * (order + 1)));
  const LatLongLevel& L = pyramid.level(projectionLevel_);
  const int n = shCount(order);
  static constexpr double nodes[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                      -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                      0.7966664774136267,  0.9602898564975363};
  static constexpr double weights[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                                        0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  const double dTheta = kPi / L.height, dPhi = kTwoPi / L.width;
  // Azimuth integrals of 1, cos(m phi), sin(m phi) over each column.
  std::vector<double> colCos(static_cast<std::size_t>(L.width) * (order + 1)), colSin(colCos.size());
  for (int x = 0; x < L.width; ++x) {
    const double p0 = x * dPhi - kPi, p1 = (x + 1) * dPhi - kPi;
    colCos[static_cast<std::size_t>(x) * (order + 1)] = dPhi;
    for (int m = 1; m <= order; ++m) {
      colCos[static_cast<std::size_t>(x) * (order + 1) + m] = (std::sin(m * p1) - std::sin(m * p0)) / m;
      colSin[static_cast<std::size_t>(x) * (order + 1) + m] = (std::cos(m * p0) - std::cos(m * p1)) / m;
    }
  }
  std::vector<Rgb> partial(static_cast<std::size_t>(L.height) * n, Rgb::Zero());
  tbb::parallel_for(0, L.height, [&](int y) {
    // Row Fourier sums of the radiance.
    std::vector<Rgb> fc(order + 1, Rgb::Zero()), fs(order + 1, Rgb::Zero());
    for (int x = 0; x < L.width; ++x) {
      const Rgb v = L.at(x, y);
      const double* c = &colCos[static_cast<std::size_t>(x) * (order + 1)];
      const double* s = &colSin[static_cast<std::size_t>(x) * (order + 1)];
      for (int m = 0; m <= order; ++m) fc[m] += c[m] * v, fs[m] += s[m] * v;
    }
    // Polar integrals of the basis at phi = 0 (Y_lm / sqrt2 = Q_lm sin^m theta for m > 0).
    std::vector<double> basis(n), polar(n, 0.0);
    for (int k = 0; k < 8; ++k) {
      const double theta = (y + 0.5 + 0.5 * nodes[k]) * dTheta;
      evaluateShBasis(order, Vec3(std::sin(theta), 0.0, std::cos(theta)), basis.data());
      const double w = 0.5 * weights[k] * dTheta * std::sin(theta);
      for (int i = 0; i < n; ++i) polar[i] += w * basis[i];
    }
    Rgb* out = &partial[static_cast<std::size_t>(y) * n];
    for (int l = 0; l <= order; ++l) {
      out[shIndex(l, 0)] = polar[shIndex(l, 0)] * fc[0];
      for (int m = 1; m <= l; ++m) {
        // polar holds sqrt2 Q sin^m; Y_l,+m = sqrt2 Q sin^m cos(m phi), Y_l,-m = ... sin(m phi).
        out[shIndex(l, m)] = polar[shIndex(l, m)] * fc[m];
        out[shIndex(l, -m)] = polar[shIndex(l, m)] * fs[m];
      }
    }
  });
  expansion_.order = order;
  expansion_.coefficients.assign(n, Rgb::Zero());
  for (int y = 0; y < L.height; ++y)
    for (int i = 0; i < n; ++i) expansion_.coefficients[i] += partial[static_cast<std::size_t>(y) * n + i];
  expansion_.convolve(lobe.zonalCoefficients(order));
}

// ---- interpolation grid ----------------------------------------------------------------------

Vec3 LatLongGrid::direction(int x, int y) const { return *map_.getDirectionFor(Vec2(x + 0.5, y + 0.5)); }

Rgb LatLongGrid::value(const Vec3& axis) const {
  const Vec2 pixel = map_.getAddressFor(axis).pixel;
  const double px = pixel.x() - 0.5, py = pixel.y() - 0.5;
  const double fx = std::floor(px), fy = std::floor(py);
  const double tx = px - fx, ty = py - fy;
  const std::array<double, 4> wx = catmullRomWeights(tx), wy = catmullRomWeights(ty);
  Rgb sum = Rgb::Zero();
  for (int j = 0; j < 4; ++j) {
    int y = static_cast<int>(fy) - 1 + j, shift = 0;
    // Across a pole, row -1 - k is row k seen from the other side (phi + pi).
    if (y < 0) y = -1 - y, shift = width_ / 2;
    if (y >= height_) y = 2 * height_ - 1 - y, shift = width_ / 2;
    y = std::clamp(y, 0, height_ - 1);
    Rgb row = Rgb::Zero();
    for (int i = 0; i < 4; ++i) {
      int x = (static_cast<int>(fx) - 1 + i + shift) % width_;
      if (x < 0) x += width_;
      row += wx[i] * values_[static_cast<std::size_t>(y) * width_ + x];
    }
    sum += wy[j] * row;
  }
  return sum;
}

// ---- reference -------------------------------------------------------------------------------

ReferenceSummer::ReferenceSummer(const Environment& environment, const PrefilterLobe& lobe, double cosCap,
                                 std::shared_ptr<const RadialTable> table)
    : lobe_(lobe), table_(std::move(table)), capAngle_(std::acos(std::clamp(cosCap, -1.0, 1.0))) {
  const Parameterization& map = *environment.map;
  double largest = 0.0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) largest = std::max(largest, map.texelSolidAngle(x, y));
  // Split texels wider than an eighth of the lobe's width (at most 8 x 8, and 2^22 samples in all:
  // 56 bytes each).
  const double texelAngle = std::sqrt(largest);
  sub_ = std::clamp(static_cast<int>(std::ceil(8.0 * texelAngle / std::max(lobe.width(), 1e-12))), 1, 8);
  while (sub_ > 1 && static_cast<double>(map.width()) * map.height() * sub_ * sub_ > 4194304.0) --sub_;
  std::vector<Vec3> inside;
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      const double omega = map.texelSolidAngle(x, y);
      if (!(omega > 0.0)) continue;
      const Rgb radiance = environment.image.at(x, y).head<3>();
      // Keep the sub-samples that lie in the texel's own part of the domain (round trip), and
      // share the texel's exact solid angle among them.
      inside.clear();
      const int region = [&] {
        for (int r = 0; r < map.regionCount(); ++r)
          if (map.region(r).contains(x, y)) return r;
        return 0;
      }();
      for (int a = 0; a < sub_; ++a) {
        for (int b = 0; b < sub_; ++b) {
          const Vec2 position(x + (b + 0.5) / sub_, y + (a + 0.5) / sub_);
          const auto d = map.getDirectionFor(position);
          if (!d) continue;
          const MapAddress back = map.getAddressFor(*d);
          Vec2 delta = back.pixel - position;
          if (map.wrapsHorizontally()) delta.x() -= std::round(delta.x() / map.width()) * map.width();
          if (back.region != region || delta.norm() > 1e-6) continue;
          inside.push_back(*d);
        }
      }
      if (inside.empty()) continue;
      const double share = omega / static_cast<double>(inside.size());
      for (const Vec3& d : inside) {
        x_.push_back(d.x()), y_.push_back(d.y()), z_.push_back(d.z());
        weight_.push_back(share);
        r_.push_back(share * radiance[0]), g_.push_back(share * radiance[1]), b_.push_back(share * radiance[2]);
      }
    }
  }
  if (capAngle_ < kPi) sortIntoCells();
}

void ReferenceSummer::sortIntoCells() {
  // Cells of a 64 x 32 lat-long (latlong_map.hpp). A point of a cell lies within (dTheta + dPhi) / 2
  // of its centre: along the meridian to its polar angle, then along that parallel (sin <= 1).
  cells_ = LatLongMap(32);
  const int count = cells_.width() * cells_.height();
  cellRadius_ = 0.5 * (kPi / cells_.height() + kTwoPi / cells_.width());
  std::vector<int> cell(x_.size());
  cellStart_.assign(static_cast<std::size_t>(count) + 1, 0);
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const Vec2 p = cells_.pixelForUnit(Vec3(x_[i], y_[i], z_[i]).normalized());
    const int cx = std::clamp(static_cast<int>(p.x()), 0, cells_.width() - 1),
              cy = std::clamp(static_cast<int>(p.y()), 0, cells_.height() - 1);
    cell[i] = cy * cells_.width() + cx;
    ++cellStart_[static_cast<std::size_t>(cell[i]) + 1];
  }
  for (int k = 0; k < count; ++k) cellStart_[k + 1] += cellStart_[k];
  std::vector<std::size_t> next(cellStart_.begin(), cellStart_.end() - 1);
  std::vector<std::size_t> order(x_.size());
  for (std::size_t i = 0; i < x_.size(); ++i) order[next[cell[i]]++] = i;
  for (auto* v : {&x_, &y_, &z_, &weight_, &r_, &g_, &b_}) {
    std::vector<double> sorted(v->size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = (*v)[order[i]];
    v->swap(sorted);
  }
  cellCentre_.clear();
  for (int y = 0; y < cells_.height(); ++y)
    for (int x = 0; x < cells_.width(); ++x) cellCentre_.push_back(*cells_.getDirectionFor(Vec2(x + 0.5, y + 0.5)));
}

namespace {
template <class Weight>
void referenceLoop(const double* xs, const double* ys, const double* zs, const double* ws, const double* rs,
                   const double* gs, const double* bs, std::size_t n, const Vec3& axis, bool positiveOnly,
                   Weight weight, double out[4]) {
  double nr = 0.0, ng = 0.0, nb = 0.0, den = 0.0;
  const double ax = axis.x(), ay = axis.y(), az = axis.z();
  for (std::size_t i = 0; i < n; ++i) {
    const double c = ax * xs[i] + ay * ys[i] + az * zs[i];
    if (positiveOnly && !(c > 0.0)) continue;
    const double w = weight(c);
    nr += w * rs[i], ng += w * gs[i], nb += w * bs[i], den += w * ws[i];
  }
  out[0] += nr, out[1] += ng, out[2] += nb, out[3] += den;
}
}  // namespace

void ReferenceSummer::sum(const Vec3& axis, std::size_t begin, std::size_t end, double out[4]) const {
  const std::size_t n = end - begin;
  const double *xs = x_.data() + begin, *ys = y_.data() + begin, *zs = z_.data() + begin, *ws = weight_.data() + begin;
  const double *rs = r_.data() + begin, *gs = g_.data() + begin, *bs = b_.data() + begin;
  if (table_) {
    const RadialTable::View view = table_->view();
    referenceLoop(
        xs, ys, zs, ws, rs, gs, bs, n, axis, false,
        [&view](double c) { return view(std::sqrt(std::max(0.0, 0.5 - 0.5 * c))); }, out);
    return;
  }
  const double scale = lobe_.weight(1.0);  // only ratios matter; keep weights near 1
  switch (lobe_.kind()) {
    case LobeKind::Irradiance:
      referenceLoop(
          xs, ys, zs, ws, rs, gs, bs, n, axis, true, [](double c) { return c; }, out);
      break;
    case LobeKind::Phong: {
      const double e = lobe_.phongExponent();
      referenceLoop(
          xs, ys, zs, ws, rs, gs, bs, n, axis, true, [e](double c) { return e == 0.0 ? 1.0 : std::pow(c, e); }, out);
      break;
    }
    default:
      referenceLoop(
          xs, ys, zs, ws, rs, gs, bs, n, axis, false, [&](double c) { return lobe_.weight(c) / scale; }, out);
      break;
  }
}

Rgb ReferenceSummer::value(const Vec3& axis) const {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  if (cellStart_.empty()) {
    sum(axis, 0, x_.size(), s);
  } else {
    const double reach = std::cos(std::min(kPi, capAngle_ + cellRadius_));
    for (std::size_t k = 0; k < cellCentre_.size(); ++k)
      if (cellStart_[k + 1] > cellStart_[k] && axis.dot(cellCentre_[k]) >= reach)
        sum(axis, cellStart_[k], cellStart_[k + 1], s);
  }
  if (s[3] > 0.0) return lobe_.mass() * Rgb(s[0], s[1], s[2]) / s[3];
  // The lobe fell between every sample: the nearest sample's radiance.
  std::size_t best = 0;
  double bestCos = -2.0;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const double c = axis.x() * x_[i] + axis.y() * y_[i] + axis.z() * z_[i];
    if (c > bestCos) bestCos = c, best = i;
  }
  if (x_.empty()) return Rgb::Zero();
  return lobe_.mass() * Rgb(r_[best], g_[best], b_[best]) / weight_[best];
}

}  // namespace brdfbake::detail
