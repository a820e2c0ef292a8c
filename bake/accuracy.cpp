#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>

namespace brdfbake {

namespace {

// Share of the highlight set drawn uniformly, so that every direction has some density (the
// importance weights stay finite, and a lobe the grid misses is still met).
constexpr double kUniformShare = 0.1;

double signal(const Rgb& value) { return value.abs().maxCoeff(); }

Vec3 uniformDirection(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  for (;;) {
    const Vec3 g(gauss(rng), gauss(rng), gauss(rng));
    if (g.norm() > 1e-12) return g.normalized();
  }
}

// A density over the sphere, constant per cell of a cube grid in face coordinates (s, t) and
// proportional to the function's largest value at the cell's centre and corners.
class CubeGridDensity {
 public:
  CubeGridDensity(const MapFunction& exact, int cells) : n_(cells) {
    const int corners = n_ + 1;
    std::vector<double> cornerValue(6 * corners * corners), centreValue(6 * n_ * n_);
    tbb::parallel_for(0, 6 * corners, [&](int row) {
      const auto face = static_cast<CubeMap::Face>(row / corners);
      const int j = row % corners;
      for (int i = 0; i < corners; ++i)
        cornerValue[row * corners + i] = signal(exact.evaluate(CubeMap::faceDirection(face, Vec2(i, j) / n_)));
    });
    tbb::parallel_for(0, 6 * n_, [&](int row) {
      const auto face = static_cast<CubeMap::Face>(row / n_);
      const int j = row % n_;
      for (int i = 0; i < n_; ++i)
        centreValue[row * n_ + i] = signal(exact.evaluate(CubeMap::faceDirection(face, Vec2(i + 0.5, j + 0.5) / n_)));
    });
    cumulative_.resize(6 * n_ * n_);
    double total = 0.0;
    for (int face = 0; face < 6; ++face)
      for (int j = 0; j < n_; ++j)
        for (int i = 0; i < n_; ++i) {
          const int c = (face * corners + j) * corners + i;
          const double value = std::max({centreValue[(face * n_ + j) * n_ + i], cornerValue[c], cornerValue[c + 1],
                                         cornerValue[c + corners], cornerValue[c + corners + 1]});
          total += value * cellSolidAngle(i, j);
          cumulative_[(face * n_ + j) * n_ + i] = total;
        }
  }

  double total() const { return cumulative_.back(); }

  Vec3 sample(std::mt19937& rng) const {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double u = unit(rng) * total();
    const auto cell =
        static_cast<int>(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin());
    const int index = std::min(cell, static_cast<int>(cumulative_.size()) - 1);
    const int face = index / (n_ * n_), j = (index / n_) % n_, i = index % n_;
    return CubeMap::faceDirection(static_cast<CubeMap::Face>(face), Vec2(i + unit(rng), j + unit(rng)) / n_);
  }

  // Probability density per steradian at unit direction r.
  double density(const Vec3& r) const {
    const auto [face, st] = CubeMap::faceCoordinates(r);
    const int i = std::clamp(static_cast<int>(st.x() * n_), 0, n_ - 1),
              j = std::clamp(static_cast<int>(st.y() * n_), 0, n_ - 1);
    const int index = (static_cast<int>(face) * n_ + j) * n_ + i;
    const double mass = cumulative_[index] - (index > 0 ? cumulative_[index - 1] : 0.0);
    // Uniform in (s, t) over a cell of area 1/n^2; dw = 4 ds dt / (1 + sc^2 + tc^2)^(3/2).
    const double sc = 2.0 * st.x() - 1.0, tc = 2.0 * st.y() - 1.0;
    return mass / total() * n_ * n_ * std::pow(1.0 + sc * sc + tc * tc, 1.5) / 4.0;
  }

 private:
  // Solid angle of cell (i, j) of a face, by its centre's density (weights only need to be close).
  double cellSolidAngle(int i, int j) const {
    const double sc = 2.0 * (i + 0.5) / n_ - 1.0, tc = 2.0 * (j + 0.5) / n_ - 1.0;
    return 4.0 / (n_ * n_) / std::pow(1.0 + sc * sc + tc * tc, 1.5);
  }

  int n_;
  std::vector<double> cumulative_;
};

struct Accumulator {
  double sumSquares = 0.0, weight = 0.0, worst = 0.0;

  void add(double squaredError, double absoluteError, double w) {
    sumSquares += w * squaredError;
    weight += w;
    worst = std::max(worst, absoluteError);
  }
  double rms() const { return weight > 0.0 ? std::sqrt(sumSquares / weight) : 0.0; }
};

}  // namespace

void ErrorOptions::validate() const {
  require(samples >= 1, "error measurement needs at least one sample, got " + std::to_string(samples));
  require(highlightGrid >= 8 && highlightGrid <= 4096,
          "the highlight grid needs 8 to 4096 cells per face side, got " + std::to_string(highlightGrid));
}

double ErrorStats::bound(bool visibleLookups) const {
  return std::max(highlightRms, visibleLookups ? visibleRms : rms);
}

ErrorProbes::ErrorProbes(const MapFunction& exact, const ErrorOptions& options) {
  options.validate();
  std::mt19937 rng(options.seed);
  for (int k = 0; k < options.samples; ++k) uniform_.push_back({uniformDirection(rng), Rgb::Zero()});
  if (options.visibleSphere) {
    std::uniform_real_distribution<double> square(-1.0, 1.0);
    while (static_cast<int>(visible_.size()) < options.samples) {
      const double x = square(rng), y = square(rng), rho2 = x * x + y * y;
      if (rho2 >= 1.0) continue;
      const double nz = std::sqrt(1.0 - rho2);
      visible_.push_back({Vec3(2 * nz * x, 2 * nz * y, 2 * nz * nz - 1), Rgb::Zero()});
    }
  }
  const CubeGridDensity grid(exact, options.highlightGrid);
  const double gridShare = grid.total() > 0.0 ? 1.0 - kUniformShare : 0.0;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < options.samples; ++k)
    highlight_.push_back({unit(rng) < gridShare ? grid.sample(rng) : uniformDirection(rng), Rgb::Zero()});

  for (auto* set : {&uniform_, &visible_})
    tbb::parallel_for(std::size_t(0), set->size(),
                      [&](std::size_t i) { (*set)[i].exact = exact.evaluate((*set)[i].direction); });
  tbb::parallel_for(std::size_t(0), highlight_.size(), [&](std::size_t i) {
    Probe& probe = highlight_[i];
    probe.exact = exact.evaluate(probe.direction);
    const double density =
        (1.0 - gridShare) / (4.0 * kPi) + (gridShare > 0.0 ? gridShare * grid.density(probe.direction) : 0.0);
    probe.weight = signal(probe.exact) / density;
  });
}

ErrorStats ErrorProbes::measure(const std::function<Rgb(const Vec3&)>& lookup, double rimCos,
                                bool visibleSphere) const {
  return measureAt([&](std::size_t, const Vec3& direction) { return lookup(direction); }, rimCos, visibleSphere);
}

ErrorStats ErrorProbes::measureValues(const std::vector<Rgb>& looked, double rimCos, bool visibleSphere) const {
  const std::size_t expected = uniform_.size() + (visibleSphere ? visible_.size() : 0) + highlight_.size();
  require(looked.size() == expected, "measureValues needs one value per direction of directions()");
  return measureAt([&](std::size_t index, const Vec3&) { return looked[index]; }, rimCos, visibleSphere);
}

ErrorStats ErrorProbes::measureAt(const std::function<Rgb(std::size_t, const Vec3&)>& lookup, double rimCos,
                                  bool visibleSphere) const {
  double peak = 0.0;
  // `first`: the index of the set's first direction in directions(visibleSphere).
  auto accumulate = [&](const std::vector<Probe>& set, std::size_t first, bool weighted) {
    Accumulator acc;
    for (std::size_t i = 0; i < set.size(); ++i) {
      const Probe& probe = set[i];
      if (-probe.direction.z() > rimCos) continue;
      const Rgb error = lookup(first + i, probe.direction) - probe.exact;
      peak = std::max(peak, signal(probe.exact));
      acc.add(error.square().sum() / 3.0, error.abs().maxCoeff(), weighted ? probe.weight : 1.0);
    }
    return acc;
  };
  const bool visible = visibleSphere && !visible_.empty();
  const std::size_t highlightFirst = uniform_.size() + (visibleSphere ? visible_.size() : 0);
  const Accumulator uniform = accumulate(uniform_, 0, false);
  const Accumulator highlight = accumulate(highlight_, highlightFirst, true);
  const Accumulator visibleAcc = visible ? accumulate(visible_, uniform_.size(), false) : uniform;
  ErrorStats stats;
  stats.peak = peak;
  const double scale = peak > 0.0 ? 1.0 / peak : 1.0;
  stats.rms = uniform.rms() * scale;
  stats.max = uniform.worst * scale;
  stats.visibleRms = visibleAcc.rms() * scale;
  stats.highlightRms = highlight.weight > 0.0 ? highlight.rms() * scale : stats.rms;
  stats.highlightMax = highlight.worst * scale;
  return stats;
}

std::vector<Vec3> ErrorProbes::directions(bool visibleSphere) const {
  std::vector<Vec3> out;
  out.reserve(uniform_.size() + visible_.size() + highlight_.size());
  for (const auto* set : {&uniform_, &visible_, &highlight_}) {
    if (set == &visible_ && !visibleSphere) continue;
    for (const Probe& probe : *set) out.push_back(probe.direction);
  }
  return out;
}

ErrorStats measureSparseLookups(const ErrorProbes& probes, long long texelCount,
                                const std::function<void(const Vec3&, TexelTaps&)>& taps,
                                const std::function<Rgb(long long)>& texel, double rimCos, bool visibleSphere,
                                const Context& context) {
  require(texelCount >= 1, "a map needs at least one texel");
  // Each texel any probe reads gets an id, in the order first read: a table over the texels
  // while it is small, a hash map beyond.
  constexpr long long kDenseLimit = 1LL << 24;
  std::vector<int> denseId(texelCount <= kDenseLimit ? static_cast<std::size_t>(texelCount) : 0, -1);
  std::unordered_map<long long, int> sparseId;
  std::vector<long long> keys;
  auto idOf = [&](long long key) {
    require(key >= 0 && key < texelCount, "a lookup tap lies outside the map");
    int& id = denseId.empty() ? sparseId.try_emplace(key, -1).first->second : denseId[static_cast<std::size_t>(key)];
    if (id < 0) {
      id = static_cast<int>(keys.size());
      keys.push_back(key);
    }
    return id;
  };
  const std::vector<Vec3> directions = probes.directions(visibleSphere);
  std::vector<TexelTaps> read(directions.size());
  for (std::size_t i = 0; i < directions.size(); ++i) {
    taps(directions[i], read[i]);
    for (int k = 0; k < read[i].count; ++k) read[i].index[k] = idOf(read[i].index[k]);
  }
  std::vector<Rgb> texels(keys.size());
  tbb::task_arena arena(context.arenaThreads());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        context.checkCancelled();
                        for (std::size_t i = range.begin(); i < range.end(); ++i) texels[i] = texel(keys[i]);
                      });
  });
  std::vector<Rgb> looked(directions.size(), Rgb::Zero());
  for (std::size_t i = 0; i < directions.size(); ++i)
    for (int k = 0; k < read[i].count; ++k)
      looked[i] += read[i].weight[k] * texels[static_cast<std::size_t>(read[i].index[k])];
  return probes.measureValues(looked, rimCos, visibleSphere);
}

ErrorStats measureLookupError(const std::function<Rgb(const Vec3&)>& lookup, const MapFunction& exact,
                              const ErrorOptions& options, double rimCos, bool visibleSphere) {
  ErrorOptions drawn = options;
  drawn.visibleSphere = visibleSphere;
  return ErrorProbes(exact, drawn).measure(lookup, rimCos, visibleSphere);
}

namespace {

// Sphere maps are also measured over a visible sphere's lookups.
bool visibleLookups(const Parameterization& map, bool visibleSphere) {
  return map.kind() == ParameterizationKind::Sphere && visibleSphere;
}

}  // namespace

double mapRimCos(ParameterizationKind kind, int resolution) {
  if (kind != ParameterizationKind::Sphere) return 2.0;
  // The angle two rim texels span, 4 sqrt(2/N) (docs/conventions.md); below 4 texels across it would
  // cover the whole sphere, and nothing is left out.
  const double band = 4.0 * std::sqrt(2.0 / resolution);
  return band < kPi ? std::cos(band) : 2.0;
}

ErrorStats measureMapError(const Image& image, const Parameterization& map, const ErrorProbes& probes,
                           bool visibleSphere) {
  return probes.measure([&](const Vec3& r) -> Rgb { return sampleBilinear(image, map, r).head<3>(); },
                        mapRimCos(map.kind(), map.resolution()), visibleLookups(map, visibleSphere));
}

ErrorStats estimateMapError(const Parameterization& map, const MapFunction& function, int samplesPerTexel,
                            const ErrorProbes& probes, bool visibleSphere, const Context& context) {
  require(samplesPerTexel >= 1, "samples per texel must be >= 1");
  const long long width = map.width();
  auto taps = [&](const Vec3& r, TexelTaps& out) {
    const BilinearTaps b = bilinearTaps(map, r);
    out.count = 4;
    out.index[0] = b.ya * width + b.xa, out.weight[0] = (1 - b.wx) * (1 - b.wy);
    out.index[1] = b.ya * width + b.xb, out.weight[1] = b.wx * (1 - b.wy);
    out.index[2] = b.yb * width + b.xa, out.weight[2] = (1 - b.wx) * b.wy;
    out.index[3] = b.yb * width + b.xb, out.weight[3] = b.wx * b.wy;
  };
  auto texel = [&](long long index) -> Rgb {
    const Rgb value =
        bakeTexel(map, function, static_cast<int>(index % width), static_cast<int>(index / width), samplesPerTexel);
    return value.cast<float>().cast<double>();  // as an Image stores it
  };
  return measureSparseLookups(probes, width * map.height(), taps, texel, mapRimCos(map.kind(), map.resolution()),
                              visibleLookups(map, visibleSphere), context);
}

ErrorStats measureMapError(const Image& image, const Parameterization& map, const MapFunction& exact,
                           const ErrorOptions& options) {
  return measureMapError(image, map, ErrorProbes(exact, options), options.visibleSphere);
}

}  // namespace brdfbake
