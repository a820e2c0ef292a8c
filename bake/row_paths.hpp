#pragma once
// What the baker's row paths share (bake/baker.cpp, radial_paths.cpp, microfacet_paths.cpp): how
// a texel's samples are laid out and mapped, tabulated lobes, a sphere map's sample normals, and
// the paths themselves behind one interface. Private to bake/.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/maps/radial_table.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace brdfbake::bake_detail {

// ---------------------------------------------------------------------------------------------
// Set-up shared by every path.

/// Rows of the most nearly square grid of `samples` cells (rows <= columns, rows columns = samples).
inline int gridRows(int samples) {
  int rows = static_cast<int>(std::sqrt(static_cast<double>(samples)));
  while (samples % rows != 0) --rows;
  return rows;
}

/// Where the samples of a texel lie: a columns x rows grid (the most nearly square with
/// columns rows = samples), at cell centres; px of every sample of a map row, texel by texel.
struct SampleLayout {
  int columns = 1, rows = 1, width = 0;
  std::vector<double> offsetY;  // [rows]
  std::vector<double> px;       // [width * columns]: x + offset of sample i of texel x

  SampleLayout(int samplesPerTexel, int mapWidth) : width(mapWidth) {
    rows = gridRows(samplesPerTexel);
    columns = samplesPerTexel / rows;
    for (int j = 0; j < rows; ++j) offsetY.push_back((j + 0.5) / rows);
    px.resize(static_cast<std::size_t>(width) * columns);
    for (int x = 0; x < width; ++x)
      for (int i = 0; i < columns; ++i) px[x * columns + i] = x + (i + 0.5) / columns;
  }
  int rowSamples() const { return width * columns; }
};

/// The directions of one row of samples (structure of arrays), and per texel how many were valid.
struct SampleRow {
  std::vector<double> x, y, z;
  std::vector<unsigned char> valid;
  std::vector<int> counted;
  explicit SampleRow(const SampleLayout& layout)
      : x(layout.rowSamples()),
        y(layout.rowSamples()),
        z(layout.rowSamples()),
        valid(layout.rowSamples()),
        counted(layout.width, 0) {}
};

/// Maps the samples at height py of every run of texels with needed[x] set, counting valid ones.
inline void mapSampleRow(const Parameterization& map, const SampleLayout& layout, double py,
                         const std::vector<unsigned char>& needed, SampleRow& row) {
  const int width = layout.width, columns = layout.columns;
  for (int x0 = 0; x0 < width;) {
    if (!needed[x0]) {
      ++x0;
      continue;
    }
    int x1 = x0;
    while (x1 < width && needed[x1]) ++x1;
    const int first = x0 * columns, count = (x1 - x0) * columns;
    map.getDirectionsForRow(py, layout.px.data() + first, count, row.x.data() + first, row.y.data() + first,
                            row.z.data() + first, row.valid.data() + first);
    for (int s = first; s < first + count; ++s) row.counted[s / columns] += row.valid[s];
    x0 = x1;
  }
}

inline std::vector<double> rowCoverage(const Parameterization& map, int y) {
  std::vector<double> coverage(map.width());
  map.texelCoverageRow(y, coverage.data());
  return coverage;
}

/// Texel x of row y = sums[x] / counted[x] (0 with no valid sample), alpha = coverage.
inline void writeRow(Image& image, int y, const std::vector<Rgb>& sums, const std::vector<int>& counted,
                     const std::vector<double>& coverage) {
  for (int x = 0; x < image.width(); ++x) {
    const Rgb mean = counted[x] > 0 ? Rgb(sums[x] / counted[x]) : Rgb::Zero();
    image.set(x, y, Rgba(mean[0], mean[1], mean[2], coverage[x]));
  }
}

/// Chord |a - b| between unit directions: a metric on the sphere, 2u for a radial table.
inline double chord(double ax, double ay, double az, const Vec3& b) {
  return std::sqrt((ax - b.x()) * (ax - b.x()) + (ay - b.y()) * (ay - b.y()) + (az - b.z()) * (az - b.z()));
}

/// One way of computing a map row. Rows are independent; bakeRow is called from worker threads.
class RowPath {
 public:
  virtual ~RowPath() = default;
  virtual void bakeRow(int y, Image& image) const = 0;
};

// ---------------------------------------------------------------------------------------------
// Radial paths: each lobe's profile tabulated once (RadialTable), looked up per sample.

struct TabulatedLobe {
  Vec3 axis;
  Rgb weight;
  RadialTable table;
  /// Narrower than the sample spacing around its axis: deposited (depositDeltaLobes), not sampled.
  bool delta = false;
};

/// Each radial lobe's profile tabulated, and whether it is narrower than the sample spacing.
std::vector<TabulatedLobe> tabulateLobes(const std::vector<RadialLobe>& radial, const Parameterization& map,
                                         const BakeOptions& options);

/// True for a sphere map of lobes all about the view (+z): then u is the map radius.
inline bool allAboutViewAxis(const Parameterization& map, const std::vector<TabulatedLobe>& lobes) {
  return map.kind() == ParameterizationKind::Sphere &&
         std::all_of(lobes.begin(), lobes.end(),
                     [](const TabulatedLobe& l) { return (l.axis - Vec3::UnitZ()).squaredNorm() < 1e-30; });
}

/// anyActive[x] for some lobe.
struct RowCulling {
  std::vector<unsigned char> active, anyActive;
};

/// Sums of the radial lobes' table values over a row's samples, [lobe][texel], and the texel
/// means they make (lobe weights are per light and channel: applied once per texel).
inline void writeLobeRow(Image& image, int y, const std::vector<TabulatedLobe>& lobes,
                         const std::vector<double>& lobeSums, const std::vector<int>& counted,
                         const std::vector<double>& coverage) {
  const int width = image.width();
  for (int x = 0; x < width; ++x) {
    Rgb sum = Rgb::Zero();
    for (std::size_t k = 0; k < lobes.size(); ++k) sum += lobes[k].weight * lobeSums[k * width + x];
    const Rgb mean = counted[x] > 0 ? Rgb(sum * (1.0 / counted[x])) : Rgb::Zero();
    image.set(x, y, Rgba(mean[0], mean[1], mean[2], coverage[x]));
  }
}

/// The unit normals n = (x, y, sqrt(1 - x^2 - y^2)) of a sphere map's samples, row by row, for
/// paths that need only n (r = 2 n_z n - v with v = +z): the disc position itself, with the map's

class SphereNormalRow {
 public:
  /// withInverse: also 1 / n_z (the microfacet path's 1 / n.v).
  SphereNormalRow(const Parameterization& map, const SampleLayout& layout, bool withInverse)
      : twoOverN_(2.0 / map.resolution()),
        count_(layout.rowSamples()),
        withInverse_(withInverse),
        sx_(scratch(count_)),
        nx_(scratch(count_)),
        ny_(scratch(count_)),
        nz_(scratch(count_)),
        inverseNz_(withInverse ? scratch(count_) : nullptr) {
    for (int s = 0; s < count_; ++s) sx_[s] = layout.px[s] * twoOverN_ - 1.0;
  }

  /// The normals of samples [begin, end) at height py (pixels). Samples inside the rim (a middle
  /// run, as sx increases along the row) in one branch-free loop, those outside pulled one by one.
  void compute(double py, int begin, int end) {
    constexpr double kRim2 = (1.0 - 1e-15) * (1.0 - 1e-15);  // SphereMap's rim radius, squared
    const double sy = 1.0 - py * twoOverN_, sy2 = sy * sy;
    const double* __restrict sx = sx_.get();
    double* __restrict nx = nx_.get();
    double* __restrict ny = ny_.get();
    double* __restrict nz = nz_.get();
    int first = begin, last = end;
    while (first < end && sx[first] * sx[first] + sy2 > kRim2) ++first;
    while (last > first && sx[last - 1] * sx[last - 1] + sy2 > kRim2) --last;
    for (int s = first; s < last; ++s) {
      nx[s] = sx[s];
      ny[s] = sy;
      nz[s] = std::sqrt(1.0 - (sx[s] * sx[s] + sy2));
    }
    const auto pulled = [&](int s) {
      const double pull = std::sqrt(kRim2 / (sx[s] * sx[s] + sy2));
      nx[s] = sx[s] * pull;
      ny[s] = sy * pull;
      nz[s] = std::sqrt(1.0 - kRim2);
    };
    for (int s = begin; s < first; ++s) pulled(s);
    for (int s = last; s < end; ++s) pulled(s);
    if (withInverse_) {
      double* __restrict inverseNz = inverseNz_.get();
      for (int s = begin; s < end; ++s) inverseNz[s] = 1.0 / nz[s];
    }
  }
  void compute(double py) { compute(py, 0, count_); }
  const double* x() const { return nx_.get(); }
  const double* y() const { return ny_.get(); }
  const double* z() const { return nz_.get(); }
  const double* inverseZ() const { return inverseNz_.get(); }

  /// Uninitialised storage for n values (every path writes before it reads).
  static std::unique_ptr<double[]> scratch(int n) { return std::make_unique_for_overwrite<double[]>(n); }

 private:
  double twoOverN_;
  int count_;
  bool withInverse_;
  std::unique_ptr<double[]> sx_, nx_, ny_, nz_, inverseNz_;
};

/// Sums of consecutive runs of `columns` values (a texel's samples in one sample row) into sums[x].
inline void addTexelSums(const double* values, int width, int columns, double* sums) {
  for (int x = 0; x < width; ++x) {
    double sum = 0.0;
    for (int i = 0; i < columns; ++i) sum += values[x * columns + i];
    sums[x] += sum;
  }
}

struct TabulatedMicrofacetLobe {
  Vec3 light, half;
  double viewDotHalf;
  Rgb specular, diffuse;
  RadialTable distribution;
};

std::vector<TabulatedMicrofacetLobe> tabulateMicrofacetLobes(const std::vector<MicrofacetLobe>& lobes,
                                                             const BakeOptions& options);

/// The paths (each one class behind RowPath).
std::unique_ptr<RowPath> makeRadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                        const SampleLayout& layout);
std::unique_ptr<RowPath> makeViewAxisPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                          const SampleLayout& layout);
std::unique_ptr<RowPath> makeSphereRadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                              const SampleLayout& layout);
std::unique_ptr<RowPath> makeMicrofacetPath(const Parameterization& map, const MapFunction& function, const Vec3& view,
                                            const std::vector<TabulatedMicrofacetLobe>& lobes,
                                            const SampleLayout& layout);
std::unique_ptr<RowPath> makeSphereMicrofacetPath(const Parameterization& map,
                                                  const std::vector<TabulatedMicrofacetLobe>& lobes,
                                                  const SampleLayout& layout);
/// Deposits the lobes narrower than the sample spacing (see radial_paths.cpp); returns how many.
int depositDeltaLobes(const Parameterization& map, const std::vector<TabulatedLobe>& lobes, Image& image);

}  // namespace brdfbake::bake_detail
