#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <tbb/parallel_for.h>

#include <array>
#include <bit>

namespace brdfbake {

int mipResolution(int resolution, int level) {
  require(resolution >= 1 && level >= 0, "mip level needs resolution >= 1 and level >= 0");
  return level >= 31 ? 1 : std::max(1, resolution >> level);
}

int mipLevelCount(int resolution) {
  require(resolution >= 1, "resolution must be >= 1, got " + std::to_string(resolution));
  int levels = 1;
  while ((resolution >> levels) >= 1) ++levels;
  return levels;
}

namespace {

// 8-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr std::array<double, 8> kNodes{-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                       -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                       0.7966664774136267,  0.9602898564975363};
constexpr std::array<double, 8> kWeights{0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                         0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                         0.2223810344533745, 0.1012285362903763};

// ∫∫ 4 / (1 + x^2 + y^2)^2 over [x0, x1] x [y0, y1] (the stereographic density, also outside the disc).
double stereographicArea(double x0, double x1, double y0, double y1) {
  double sum = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double x = 0.5 * (x0 + x1) + 0.5 * (x1 - x0) * kNodes[i];
    for (int j = 0; j < 8; ++j) {
      const double y = 0.5 * (y0 + y1) + 0.5 * (y1 - y0) * kNodes[j];
      const double d = 1.0 + x * x + y * y;
      sum += kWeights[i] * kWeights[j] * 4.0 / (d * d);
    }
  }
  return sum * 0.25 * (x1 - x0) * (y1 - y0);
}

}  // namespace

double mipTexelWeight(const Parameterization& map, int x, int y) {
  if (map.kind() == ParameterizationKind::Paraboloid) {
    const int n = map.resolution();
    const double scale = 2.0 / n;
    const int local = x % n;
    return stereographicArea(local * scale - 1.0, (local + 1) * scale - 1.0, 1.0 - (y + 1) * scale, 1.0 - y * scale);
  }
  return map.texelSolidAngle(x, y);
}

Image downsampleEnvironment(const Image& fine, const Parameterization& fineMap) {
  require(fine.width() == fineMap.width() && fine.height() == fineMap.height(),
          "downsample: image does not match its map");
  require(fineMap.resolution() > 1, "downsample: a map of resolution 1 has no coarser level");
  const auto coarseMap = makeParameterization(fineMap.kind(), fineMap.resolution() / 2);
  Image coarse(coarseMap->width(), coarseMap->height(), Rgba::Zero());
  // Lat-long texels of one row share their solid angle: one weight per row.
  const bool rowWeights = fineMap.kind() == ParameterizationKind::LatLong;
  for (int r = 0; r < fineMap.regionCount(); ++r) {
    const TexelRect f = fineMap.region(r), c = coarseMap->region(r);
    // The coarse column and row holding each fine texel centre, and the fine rows of each coarse row.
    std::vector<int> coarseColumn(static_cast<std::size_t>(f.width));
    for (int x = 0; x < f.width; ++x)
      coarseColumn[x] = std::min(c.width - 1, static_cast<int>((x + 0.5) * c.width / f.width));
    std::vector<std::vector<int>> fineRows(static_cast<std::size_t>(c.height));
    for (int y = 0; y < f.height; ++y)
      fineRows[std::min(c.height - 1, static_cast<int>((y + 0.5) * c.height / f.height))].push_back(y);
    tbb::parallel_for(0, c.height, [&](int cy) {
      std::vector<double> sums(static_cast<std::size_t>(c.width) * 4, 0.0);   // rgb, weight
      std::vector<double> plain(static_cast<std::size_t>(c.width) * 4, 0.0);  // rgb, count
      for (const int y : fineRows[cy]) {
        const double rowWeight = rowWeights ? mipTexelWeight(fineMap, f.x0, f.y0 + y) : 0.0;
        const float* row = fine.data() + fine.index(f.x0, f.y0 + y);
        for (int x = 0; x < f.width; ++x) {
          const double w = rowWeights ? rowWeight : mipTexelWeight(fineMap, f.x0 + x, f.y0 + y);
          const float* v = row + 4 * x;
          double* s = &sums[static_cast<std::size_t>(coarseColumn[x]) * 4];
          double* p = &plain[static_cast<std::size_t>(coarseColumn[x]) * 4];
          for (int k = 0; k < 3; ++k) s[k] += w * v[k], p[k] += v[k];
          s[3] += w, p[3] += 1.0;
        }
      }
      for (int x = 0; x < c.width; ++x) {
        const double* s = &sums[static_cast<std::size_t>(x) * 4];
        const double* p = &plain[static_cast<std::size_t>(x) * 4];
        Rgba value;
        if (s[3] > 0.0) {
          value << s[0] / s[3], s[1] / s[3], s[2] / s[3], 0.0;
        } else {
          value << p[0] / p[3], p[1] / p[3], p[2] / p[3], 0.0;
        }
        value[3] = coarseMap->texelCoverage(c.x0 + x, c.y0 + cy);
        coarse.set(c.x0 + x, c.y0 + cy, value);
      }
    });
  }
  return coarse;
}

void fixCubeEdges(Image& image, const CubeMap& map) {
  const int n = map.resolution();
  require(image.width() == map.width() && image.height() == map.height(), "fixCubeEdges: image does not match its map");
  if (n == 1) {
    Rgba sum = Rgba::Zero();
    double weight = 0.0;
    for (int f = 0; f < 6; ++f) {
      const TexelRect r = map.region(f);
      const double w = map.texelSolidAngle(r.x0, r.y0);
      sum += w * image.at(r.x0, r.y0);
      weight += w;
    }
    for (int f = 0; f < 6; ++f) {
      const TexelRect r = map.region(f);
      Rgba v = sum / weight;
      v[3] = 1.0;
      image.set(r.x0, r.y0, v);
    }
    return;
  }
  // The texel across an edge: step half a texel out of the face and look the direction up.
  auto across = [&](int face, double lx, double ly) {
    const Vec3 d = CubeMap::faceDirection(static_cast<CubeMap::Face>(face), Vec2(lx / n, ly / n));
    const MapAddress a = map.getAddressFor(d);
    const TexelRect r = map.region(a.region);
    const int x = std::clamp(static_cast<int>(std::floor(a.pixel.x())), r.x0, r.x0 + r.width - 1);
    const int y = std::clamp(static_cast<int>(std::floor(a.pixel.y())), r.y0, r.y0 + r.height - 1);
    return std::array<int, 2>{x, y};
  };
  struct Update {
    int x, y;
    Rgba value;
  };
  std::vector<Update> updates;
  for (int f = 0; f < 6; ++f) {
    const TexelRect r = map.region(f);
    for (int ly = 0; ly < n; ++ly) {
      for (int lx = 0; lx < n; ++lx) {
        if (lx != 0 && ly != 0 && lx != n - 1 && ly != n - 1) continue;
        std::vector<std::array<int, 2>> group{{r.x0 + lx, r.y0 + ly}};
        if (lx == 0) group.push_back(across(f, -0.5, ly + 0.5));
        if (lx == n - 1) group.push_back(across(f, n + 0.5, ly + 0.5));
        if (ly == 0) group.push_back(across(f, lx + 0.5, -0.5));
        if (ly == n - 1) group.push_back(across(f, lx + 0.5, n + 0.5));
        Rgba sum = Rgba::Zero();
        double weight = 0.0;
        for (const auto& t : group) {
          const double w = map.texelSolidAngle(t[0], t[1]);
          sum += w * image.at(t[0], t[1]);
          weight += w;
        }
        Rgba v = sum / weight;
        v[3] = image.at(r.x0 + lx, r.y0 + ly)[3];
        updates.push_back({r.x0 + lx, r.y0 + ly, v});
      }
    }
  }
  for (const auto& u : updates) image.set(u.x, u.y, u.value);
}

void alignParaboloidBorder(Image& image, const ParaboloidMap& map) {
  const int n = map.resolution();
  require(image.width() == map.width() && image.height() == map.height(),
          "alignParaboloidBorder: image does not match its map");
  if (n < 4) return;
  // A ring texel qualifies when the circle enters its outer half-band: along the edge, within
  // |t| <= sqrt(1 - (1 - 1/n)^2) of the tangent point (t the map coordinate along the edge).
  const double reach = std::sqrt(1.0 - (1.0 - 1.0 / n) * (1.0 - 1.0 / n));
  auto crosses = [&](int i) {
    const double t0 = 2.0 * i / n - 1.0, t1 = 2.0 * (i + 1) / n - 1.0;
    return t1 >= -reach && t0 <= reach;
  };
  auto average = [&](int x, int y) {
    const Rgba front = image.at(x, y), back = image.at(x + n, y);
    Rgba mean = 0.5 * (front + back);
    mean[3] = front[3];
    image.set(x, y, mean);
    mean[3] = back[3];
    image.set(x + n, y, mean);
  };
  for (int i = 1; i < n - 1; ++i) {
    if (!crosses(i)) continue;
    average(i, 0), average(i, n - 1), average(0, i), average(n - 1, i);
  }
}

std::vector<Image> environmentMipChain(const Image& level0, const Parameterization& map) {
  std::vector<Image> levels{level0};
  const int count = mipLevelCount(map.resolution());
  std::unique_ptr<Parameterization> current = makeParameterization(map.kind(), map.resolution());
  if (map.kind() == ParameterizationKind::Cube) fixCubeEdges(levels[0], static_cast<const CubeMap&>(*current));
  if (map.kind() == ParameterizationKind::Paraboloid)
    alignParaboloidBorder(levels[0], static_cast<const ParaboloidMap&>(*current));
  for (int level = 1; level < count; ++level) {
    Image next = downsampleEnvironment(levels.back(), *current);
    std::unique_ptr<Parameterization> coarser = makeParameterization(map.kind(), current->resolution() / 2);
    if (map.kind() == ParameterizationKind::Cube) fixCubeEdges(next, static_cast<const CubeMap&>(*coarser));
    if (map.kind() == ParameterizationKind::Paraboloid)
      alignParaboloidBorder(next, static_cast<const ParaboloidMap&>(*coarser));
    current = std::move(coarser);
    levels.push_back(std::move(next));
  }
  return levels;
}

}  // namespace brdfbake
