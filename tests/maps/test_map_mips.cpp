// Mip chains of environment maps (maps/map_mips.hpp) against solid angles the test computes:
// closed forms for lat-long and cube texels, a brute-force integral of the stereographic density
// for paraboloid texels, and sphere-map texels from texelSolidAngle (itself checked by brute force
// in SolidAngle.MatchesBruteForceIntegrationIncludingRimTexels).
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_support.hpp"

namespace brdfbake {
namespace {

// The stereographic density 4 / (1 + x^2 + y^2)^2 (a paraboloid map's solid angle per unit area
// of its square) over [x0, x1] x [y0, y1] by the midpoint rule on `cells` x `cells` cells.
double midpointStereographic(double x0, double x1, double y0, double y1, int cells) {
  double sum = 0.0;
  for (int i = 0; i < cells; ++i) {
    const double x = x0 + (x1 - x0) * (i + 0.5) / cells;
    for (int j = 0; j < cells; ++j) {
      const double y = y0 + (y1 - y0) * (j + 0.5) / cells, d = 1.0 + x * x + y * y;
      sum += 4.0 / (d * d);
    }
  }
  return sum * (x1 - x0) * (y1 - y0) / (cells * cells);
}

// The same integral by brute force: the midpoint rule's error is c h^2 + O(h^4), so Richardson's
// (4 M(200) - M(100)) / 3 cancels the h^2 term. The O(h^4) left is below 1e-9 of the integral for
// squares of side <= 2 (the density's fourth derivatives are below 2e3, h <= 0.02).
double bruteForceStereographic(double x0, double x1, double y0, double y1) {
  return (4.0 * midpointStereographic(x0, x1, y0, y1, 200) - midpointStereographic(x0, x1, y0, y1, 100)) / 3.0;
}

TEST(MipTexelWeight, ParaboloidTexelsWeighTheStereographicDensityOverTheirSquare) {
  // Each half is N x N texels over the square [-1, 1]^2 (docs/conventions.md); the density is
  // even in x and y, so the texel's square is found whichever way its axes point.
  for (int n : {2, 5, 8}) {
    const auto map = makeParameterization(ParameterizationKind::Paraboloid, n);
    ASSERT_EQ(map->width(), 2 * n);
    double half = 0.0;
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < 2 * n; ++x) {
        const int local = x % n;
        const double x0 = -1.0 + 2.0 * local / n, y0 = -1.0 + 2.0 * y / n;
        const double expected = bruteForceStereographic(x0, x0 + 2.0 / n, y0, y0 + 2.0 / n);
        const double weight = mipTexelWeight(*map, x, y);
        EXPECT_NEAR(weight, expected, 1e-6 * expected) << n << ": (" << x << ", " << y << ")";
        if (x < n) half += weight;
        // Texels wholly inside the disc: the weight is the texel's exact solid angle.
        const double far =
            std::hypot(std::max(std::abs(x0), std::abs(x0 + 2.0 / n)), std::max(std::abs(y0), std::abs(y0 + 2.0 / n)));
        if (far < 1.0) {
          EXPECT_NEAR(weight, map->texelSolidAngle(x, y), 1e-9 * weight);
        }
      }
    }
    // A half's texels cover its whole square: the disc (2 pi, a hemisphere) and the corners.
    EXPECT_NEAR(half, bruteForceStereographic(-1, 1, -1, 1), 1e-6 * half);
    EXPECT_GT(half, kTwoPi);
  }
}

// A lat-long texel of a 2N x N map: 2 pi / 2N of azimuth times cos(theta0) - cos(theta1).
double latLongSolidAngle(int n, int y) {
  return kTwoPi / (2 * n) * (std::cos(kPi * y / n) - std::cos(kPi * (y + 1) / n));
}

// A cube-face texel: the solid angle of [u0, u1] x [v0, v1] on the face z = 1 is the sum of
// atan(u v / sqrt(1 + u^2 + v^2)) over the corners with signs.
double cubeSolidAngle(int n, int lx, int ly) {
  auto corner = [](double u, double v) { return std::atan2(u * v, std::sqrt(1.0 + u * u + v * v)); };
  const double u0 = -1.0 + 2.0 * lx / n, u1 = u0 + 2.0 / n, v0 = -1.0 + 2.0 * ly / n, v1 = v0 + 2.0 / n;
  return corner(u1, v1) - corner(u0, v1) - corner(u1, v0) + corner(u0, v0);
}

// The solid angle of texel (x, y) of `map` computed here (see the file's comment).
double solidAngle(const Parameterization& map, int x, int y) {
  switch (map.kind()) {
    case ParameterizationKind::LatLong:
      return latLongSolidAngle(map.resolution(), y);
    case ParameterizationKind::Cube:
      for (int r = 0; r < map.regionCount(); ++r) {
        const TexelRect rect = map.region(r);
        if (rect.contains(x, y)) return cubeSolidAngle(map.resolution(), x - rect.x0, y - rect.y0);
      }
      return 0.0;
    default:
      return map.texelSolidAngle(x, y);
  }
}

Image randomImage(const Parameterization& map, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  Image image(map.width(), map.height(), Rgba::Zero());
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) image.set(x, y, Rgba(u(rng), u(rng), u(rng), 1.0));
  return image;
}

TEST(EnvironmentMips, CoarseTexelsAreSolidAngleWeightedMeansOfTheFourTheyCover) {
  // Random level-0 texels, so no averaging can hide behind a smooth environment. Each region
  // (lat-long: the image; cube: a face; sphere: the disc's square) halves in both directions.
  for (auto kind : {ParameterizationKind::LatLong, ParameterizationKind::Cube, ParameterizationKind::Sphere}) {
    const auto fine = makeParameterization(kind, 16);
    const auto coarse = makeParameterization(kind, 8);
    const Image image = randomImage(*fine, 7);
    const Image down = downsampleEnvironment(image, *fine);
    ASSERT_EQ(down.width(), coarse->width());
    ASSERT_EQ(down.height(), coarse->height());
    int checked = 0;
    for (int r = 0; r < fine->regionCount(); ++r) {
      const TexelRect f = fine->region(r), c = coarse->region(r);
      for (int cy = 0; cy < c.height; ++cy) {
        for (int cx = 0; cx < c.width; ++cx) {
          Eigen::Array3d sum = Eigen::Array3d::Zero(), plain = Eigen::Array3d::Zero();
          double weight = 0.0;
          for (int k = 0; k < 4; ++k) {
            const int x = f.x0 + 2 * cx + k % 2, y = f.y0 + 2 * cy + k / 2;
            const double w = solidAngle(*fine, x, y);
            sum += w * image.at(x, y).head<3>().cast<double>();
            plain += image.at(x, y).head<3>().cast<double>() / 4.0;
            weight += w;
          }
          // Texels with no solid angle (a sphere map's corners) take the plain mean.
          const Eigen::Array3d expected = weight > 0.0 ? Eigen::Array3d(sum / weight) : plain;
          const Eigen::Array3d got = down.at(c.x0 + cx, c.y0 + cy).head<3>().cast<double>();
          EXPECT_LT((got - expected).abs().maxCoeff(), 2e-6 * expected.abs().maxCoeff())
              << toString(kind) << " coarse (" << c.x0 + cx << ", " << c.y0 + cy << ")";
          ++checked;
        }
      }
    }
    // Every coarse texel: the whole image, or for a cube its six 8 x 8 faces (half the cross).
    EXPECT_EQ(checked, kind == ParameterizationKind::Cube ? 6 * 8 * 8 : coarse->width() * coarse->height())
        << toString(kind);
  }
}

TEST(EnvironmentMips, LevelsKeepTheSolidAngleIntegral) {
  // sum over texels of (solid angle x value), with the solid angles computed here at each level,
  // is kept from level to level (the coarse texel's solid angle is the sum of the fine ones it
  // covers). Cube chains are edge-fixed at every level, which moves a little energy between edge
  // texels of unequal solid angle: 2e-3 of it at most.
  for (auto kind : {ParameterizationKind::LatLong, ParameterizationKind::Cube, ParameterizationKind::Sphere}) {
    const auto map = makeParameterization(kind, 32);
    const auto chain = environmentMipChain(randomImage(*map, 3), *map);
    ASSERT_EQ(chain.size(), 6u);
    auto integral = [&](const Image& image, int resolution) {
      const auto level = makeParameterization(kind, resolution);
      Eigen::Array3d sum = Eigen::Array3d::Zero();
      for (int y = 0; y < level->height(); ++y)
        for (int x = 0; x < level->width(); ++x)
          sum += solidAngle(*level, x, y) * image.at(x, y).head<3>().cast<double>();
      return sum;
    };
    const Eigen::Array3d base = integral(chain[0], 32);
    // Random values in [0, 4]: the integral is near 2 x 4 pi.
    EXPECT_NEAR(base.mean(), 2.0 * 4.0 * kPi, 0.05 * 8.0 * kPi) << toString(kind);
    for (int level = 1; level < 6; ++level) {
      const Eigen::Array3d value = integral(chain[level], 32 >> level);
      const double tolerance = kind == ParameterizationKind::Cube ? 2e-3 : 1e-5;
      EXPECT_LT(((value - base) / base).abs().maxCoeff(), tolerance) << toString(kind) << " level " << level;
    }
  }
}

TEST(TiledMaps, EveryLevelReadsBackAsTheSolidAngleWeightedMeanOfTheTexelsItCovers) {
  // A lat-long map of 16 (32 x 16 texels) of random values, its chain written into one tiled
  // OpenEXR and one KTX2 (rgba32f). Level k's texel (x, y) covers level 0's block of 2^k x 2^k
  // texels; its value is the block's mean weighted by the closed-form solid angles (latLongSolidAngle).
  // OpenEXR's extra level below the map's last (2 x 1 -> 1 x 1) and KTX2's one more level for
  // a 2:1 map both hold the whole sphere's mean: sum of solid angle x value / 4 pi.
  const int n = 16;
  const auto map = makeParameterization(ParameterizationKind::LatLong, n);
  const Image level0 = randomImage(*map, 9);
  const auto chain = environmentMipChain(level0, *map);
  ASSERT_EQ(chain.size(), 5u);
  auto blockMean = [&](int k, int x, int y) {
    Eigen::Array3d sum = Eigen::Array3d::Zero();
    double weight = 0.0;
    for (int j = y << k; j < (y + 1) << k; ++j)
      for (int i = x << k; i < (x + 1) << k; ++i) {
        sum += latLongSolidAngle(n, j) * level0.at(i, j).head<3>().cast<double>();
        weight += latLongSolidAngle(n, j);
      }
    return Eigen::Array3d(sum / weight);
  };
  const Eigen::Array3d sphereMean = blockMean(4, 0, 0) / 2.0 + blockMean(4, 1, 0) / 2.0;  // equal halves
  test::TempDir dir;
  const MapInfo info{ParameterizationKind::LatLong, n, kConventionVersion, {{"environment", "random"}}};
  WriteOptions rgba32f;
  rgba32f.texelFormat = TexelFormat::Rgba32Float;
  for (const std::string name : {"chain.exr", "chain.ktx2"}) {
    const auto path = dir / name;
    writeTiledMap(chain, info, path, CubeLayout::Cross, name == "chain.exr" ? WriteOptions{} : rgba32f);
    ASSERT_EQ(imageMipLevelCount(path), 6) << name;  // 32 x 16 down to 1 x 1
    for (int k = 0; k < 5; ++k) {
      const MapFile level = readMap(path, k);
      ASSERT_EQ(level.image.width(), 2 * (n >> k)) << name << " level " << k;
      for (int y = 0; y < level.image.height(); ++y)
        for (int x = 0; x < level.image.width(); ++x) {
          const Eigen::Array3d expected = blockMean(k, x, y);
          const Eigen::Array3d got = level.image.at(x, y).head<3>().cast<double>();
          EXPECT_LT((got - expected).abs().maxCoeff(), 1e-6 * expected.maxCoeff())
              << name << " level " << k << " (" << x << ", " << y << ")";
        }
    }
    const Image last = readImage(path, 5);
    ASSERT_EQ(last.width(), 1);
    EXPECT_LT((last.at(0, 0).head<3>().cast<double>() - sphereMean).abs().maxCoeff(), 1e-6 * sphereMean.maxCoeff())
        << name;
  }
}

}  // namespace
}  // namespace brdfbake
