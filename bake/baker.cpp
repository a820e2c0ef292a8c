#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/maps/radial_table.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <limits>
#include <memory>
#include <sstream>

namespace brdfbake {
namespace {

// ---------------------------------------------------------------------------------------------
// Set-up shared by every path.

/// Rows of the most nearly square grid of `samples` cells (rows <= columns, rows columns = samples).
int gridRows(int samples) {
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
void mapSampleRow(const Parameterization& map, const SampleLayout& layout, double py,
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

std::vector<double> rowCoverage(const Parameterization& map, int y) {
  std::vector<double> coverage(map.width());
  map.texelCoverageRow(y, coverage.data());
  return coverage;
}

/// Texel x of row y = sums[x] / counted[x] (0 with no valid sample), alpha = coverage.
void writeRow(Image& image, int y, const std::vector<Rgb>& sums, const std::vector<int>& counted,
              const std::vector<double>& coverage) {
  for (int x = 0; x < image.width(); ++x) {
    const Rgb mean = counted[x] > 0 ? Rgb(sums[x] / counted[x]) : Rgb::Zero();
    image.set(x, y, Rgba(mean[0], mean[1], mean[2], coverage[x]));
  }
}

/// Chord |a - b| between unit directions: a metric on the sphere, 2u for a radial table.
double chord(double ax, double ay, double az, const Vec3& b) {
  return std::sqrt((ax - b.x()) * (ax - b.x()) + (ay - b.y()) * (ay - b.y()) + (az - b.z()) * (az - b.z()));
}

/// One way of computing a map row. Rows are independent; bakeRow is called from worker threads.
class RowPath {
 public:
  virtual ~RowPath() = default;
  virtual void bakeRow(int y, Image& image) const = 0;
};

// ---------------------------------------------------------------------------------------------
// General path: the model at every sample.

class GeneralPath final : public RowPath {
 public:
  GeneralPath(const Parameterization& map, const MapFunction& function, const SampleLayout& layout)
      : map_(map), function_(function), layout_(layout) {}

  void bakeRow(int y, Image& image) const override {
    SampleRow row(layout_);
    const std::vector<unsigned char> all(layout_.width, 1);
    std::vector<Rgb> sums(layout_.width, Rgb::Zero());
    for (int j = 0; j < layout_.rows; ++j) {
      mapSampleRow(map_, layout_, y + layout_.offsetY[j], all, row);
      for (int s = 0; s < layout_.rowSamples(); ++s) {
        if (row.valid[s]) sums[s / layout_.columns] += function_.evaluate(Vec3(row.x[s], row.y[s], row.z[s]));
      }
    }
    writeRow(image, y, sums, row.counted, rowCoverage(map_, y));
  }

 private:
  const Parameterization& map_;
  const MapFunction& function_;
  const SampleLayout& layout_;
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

std::vector<TabulatedLobe> tabulateLobes(const std::vector<RadialLobe>& radial, const Parameterization& map,
                                         const BakeOptions& options) {
  std::vector<TabulatedLobe> lobes;
  for (const auto& lobe : radial) {
    TabulatedLobe t{lobe.axis.normalized(), lobe.weight, RadialTable(lobe.profile, options.profileTolerance)};
    const MapAddress at = map.getAddressFor(t.axis);
    const TexelRect rect = map.region(at.region);
    const int tx = std::clamp(static_cast<int>(at.pixel.x()), rect.x0, rect.x0 + rect.width - 1);
    const int ty = std::clamp(static_cast<int>(at.pixel.y()), rect.y0, rect.y0 + rect.height - 1);
    const double texelAngle = std::sqrt(std::max(map.texelSolidAngle(tx, ty), 1e-300));
    const double spacing = texelAngle / std::sqrt(static_cast<double>(options.samplesPerTexel));
    t.delta = 2.0 * t.table.halfEnergyAngle() < spacing && t.table.energy() != 0.0;
    lobes.push_back(std::move(t));
  }
  return lobes;
}

/// True for a sphere map of lobes all about the view (+z): then u is the map radius.
bool allAboutViewAxis(const Parameterization& map, const std::vector<TabulatedLobe>& lobes) {
  return map.kind() == ParameterizationKind::Sphere &&
         std::all_of(lobes.begin(), lobes.end(),
                     [](const TabulatedLobe& l) { return (l.axis - Vec3::UnitZ()).squaredNorm() < 1e-30; });
}

/// Which lobes may be non-zero in which texels of a row: active[k * width + x] for lobe k,
/// anyActive[x] for some lobe.
struct RowCulling {
  std::vector<unsigned char> active, anyActive;
};

/// Sums of the radial lobes' table values over a row's samples, [lobe][texel], and the texel
/// means they make (lobe weights are per light and channel: applied once per texel).
void writeLobeRow(Image& image, int y, const std::vector<TabulatedLobe>& lobes, const std::vector<double>& lobeSums,
                  const std::vector<int>& counted, const std::vector<double>& coverage) {
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
/// rim pull (SphereMap), and no inverse mapping. 1 / n_z is kept too (n.v = n_z).
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
void addTexelSums(const double* values, int width, int columns, double* sums) {
  for (int x = 0; x < width; ++x) {
    double sum = 0.0;
    for (int i = 0; i < columns; ++i) sum += values[x * columns + i];
    sums[x] += sum;
  }
}

/// Radial lobes about any axes, in any map: samples mapped through the inverse mapping, u = |d - a| / 2.
class RadialPath final : public RowPath {
 public:
  RadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes, const SampleLayout& layout)
      : map_(map), lobes_(lobes), layout_(layout) {}

  void bakeRow(int y, Image& image) const override {
    const int width = layout_.width, columns = layout_.columns;
    const std::vector<double> coverage = rowCoverage(map_, y);
    const RowCulling cull = cullRow(y, coverage);
    SampleRow row(layout_);
    std::vector<double> lobeSums(lobes_.size() * width, 0.0);
    for (int j = 0; j < layout_.rows; ++j) {
      mapSampleRow(map_, layout_, y + layout_.offsetY[j], cull.anyActive, row);
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        const RadialTable::View table = lobes_[k].table.view();
        const double ax = lobes_[k].axis.x(), ay = lobes_[k].axis.y(), az = lobes_[k].axis.z();
        double* out = &lobeSums[k * width];
        const unsigned char* on = &cull.active[k * width];
        const double *X = row.x.data(), *Y = row.y.data(), *Z = row.z.data();
        const unsigned char* ok = row.valid.data();
        for (int x = 0; x < width; ++x) {
          if (!on[x]) continue;
          double acc = 0.0;
          for (int i = 0; i < columns; ++i) {
            const int s = x * columns + i;
            const double ex = X[s] - ax, ey = Y[s] - ay, ez = Z[s] - az;
            const double value = table(0.5 * std::sqrt(ex * ex + ey * ey + ez * ez));
            acc += ok[s] ? value : 0.0;
          }
          out[x] += acc;
        }
      }
    }
    writeLobeRow(image, y, lobes_, lobeSums, row.counted, coverage);
  }

 private:
  /// A texel contributes nothing to lobe k if every direction of its footprint lies outside the
  /// table's support. A texel's directions lie within `spread` (a chord) of its centre direction,
  /// estimated from its corners with a 1.5x margin for curvature; texels the domain's boundary
  /// cuts through (0 < coverage < 1) are never culled, texels whose centre is invalid always are.
  RowCulling cullRow(int y, const std::vector<double>& coverage) const {
    const int width = layout_.width;
    const std::size_t lobeCount = lobes_.size();
    RowCulling cull{std::vector<unsigned char>(lobeCount * width, 1), std::vector<unsigned char>(width, 1)};
    std::vector<double> cx(width + 1), cy(width + 1), cz(width + 1);
    std::vector<double> tx(width + 1), ty(width + 1), tz(width + 1), bx(width + 1), by(width + 1), bz(width + 1);
    std::vector<unsigned char> cv(width + 1), tv(width + 1), bv(width + 1);
    std::vector<double> edges(width + 1), centres(width);
    for (int x = 0; x <= width; ++x) edges[x] = x;
    for (int x = 0; x < width; ++x) centres[x] = x + 0.5;
    map_.getDirectionsForRow(y + 0.5, centres.data(), width, cx.data(), cy.data(), cz.data(), cv.data());
    map_.getDirectionsForRow(y, edges.data(), width + 1, tx.data(), ty.data(), tz.data(), tv.data());
    map_.getDirectionsForRow(y + 1, edges.data(), width + 1, bx.data(), by.data(), bz.data(), bv.data());
    for (int x = 0; x < width; ++x) {
      if (!cv[x]) {
        for (std::size_t k = 0; k < lobeCount; ++k) cull.active[k * width + x] = 0;
        cull.anyActive[x] = 0;
        continue;
      }
      const Vec3 centre(cx[x], cy[x], cz[x]);
      double spread = 0.0;
      for (int c = 0; c < 2; ++c) {
        if (tv[x + c]) spread = std::max(spread, chord(tx[x + c], ty[x + c], tz[x + c], centre));
        if (bv[x + c]) spread = std::max(spread, chord(bx[x + c], by[x + c], bz[x + c], centre));
      }
      spread = 1.5 * spread + 1e-9;
      const bool boundary = coverage[x] > 0.0 && coverage[x] < 1.0;
      bool any = false;
      for (std::size_t k = 0; k < lobeCount; ++k) {
        const RadialTable& table = lobes_[k].table;
        bool on = false;
        if (!lobes_[k].delta) {
          on = boundary;
          if (!on) {
            const double distance = chord(cx[x], cy[x], cz[x], lobes_[k].axis);
            const double lo = 0.5 * (distance - spread), hi = 0.5 * (distance + spread);
            on = hi >= table.minU() && lo <= table.maxU();
          }
        }
        cull.active[k * width + x] = on;
        any = any || on;
      }
      cull.anyActive[x] = any;
    }
    return cull;
  }

  const Parameterization& map_;
  const std::vector<TabulatedLobe>& lobes_;
  const SampleLayout& layout_;
};

/// Radial lobes about the view in a sphere map: u = sin(theta/2) of r about +z is the radius in
/// the unit disc, so the table is indexed by the sample's disc position with no inverse mapping.
class ViewAxisPath final : public RowPath {
 public:
  ViewAxisPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes, const SampleLayout& layout)
      : map_(map), lobes_(lobes), layout_(layout), twoOverN_(2.0 / map.resolution()) {}

  void bakeRow(int y, Image& image) const override {
    const int width = layout_.width, columns = layout_.columns;
    const std::vector<unsigned char> active = cullRow(y);
    std::vector<double> lobeSums(lobes_.size() * width, 0.0);
    for (int j = 0; j < layout_.rows; ++j) {
      const double sy = 1.0 - (y + layout_.offsetY[j]) * twoOverN_;
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        const RadialTable::View table = lobes_[k].table.view();
        double* out = &lobeSums[k * width];
        const double* px = layout_.px.data();
        const unsigned char* on = &active[k * width];
        for (int x = 0; x < width; ++x) {
          if (!on[x]) continue;
          double acc = 0.0;
          for (int i = 0; i < columns; ++i) {
            const double sx = px[x * columns + i] * twoOverN_ - 1.0;
            acc += table(std::sqrt(sx * sx + sy * sy));
          }
          out[x] += acc;
        }
      }
    }
    const std::vector<int> counted(width, layout_.rows * columns);
    writeLobeRow(image, y, lobes_, lobeSums, counted, rowCoverage(map_, y));
  }

 private:
  /// active[k * width + x]: the range of the disc radius over texel x's square meets lobe k's support.
  std::vector<unsigned char> cullRow(int y) const {
    const int width = layout_.width;
    std::vector<unsigned char> active(lobes_.size() * width, 0);
    for (int x = 0; x < width; ++x) {
      const double x0 = x * twoOverN_ - 1.0, x1 = (x + 1) * twoOverN_ - 1.0;
      const double y0 = 1.0 - (y + 1) * twoOverN_, y1 = 1.0 - y * twoOverN_;
      const double nearX = std::clamp(0.0, x0, x1), nearY = std::clamp(0.0, y0, y1);
      const double lo = std::min(1.0, std::sqrt(nearX * nearX + nearY * nearY));
      const double hi = std::min(1.0, std::sqrt(std::max(x0 * x0, x1 * x1) + std::max(y0 * y0, y1 * y1)));
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        const RadialTable& table = lobes_[k].table;
        active[k * width + x] = !lobes_[k].delta && hi >= table.minU() && lo <= table.maxU();
      }
    }
    return active;
  }

  const Parameterization& map_;
  const std::vector<TabulatedLobe>& lobes_;
  const SampleLayout& layout_;
  double twoOverN_;
};

/// Radial lobes about any axes in a sphere map (v = +z): r = 2 n_z n - v from the sample's normal
/// (SphereNormalRow), u = |r - a| / 2 as on the radial path, with no inverse mapping. Texels are
/// culled in runs of kBlock along a row (cullBlocks).
class SphereRadialPath final : public RowPath {
 public:
  static constexpr int kBlock = 16;

  SphereRadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes, const SampleLayout& layout)
      : map_(map),
        lobes_(lobes),
        layout_(layout),
        twoOverN_(2.0 / map.resolution()),
        blocks_((layout.width + kBlock - 1) / kBlock) {
    for (const auto& lobe : lobes) {
      const RadialTable& table = lobe.table;
      const bool sampled = !lobe.delta && table.minU() <= table.maxU();
      supports_.push_back({sampled, 2.0 * std::asin(table.minU()), 2.0 * std::asin(table.maxU()),
                           angleBetween(-Vec3::UnitZ(), lobe.axis)});
    }
  }

  void bakeRow(int y, Image& image) const override {
    const int width = layout_.width, columns = layout_.columns;
    const std::vector<unsigned char> active = cullBlocks(y);
    SphereNormalRow normals(map_, layout_, false);
    const auto u = SphereNormalRow::scratch(layout_.rowSamples());
    std::vector<double> lobeSums(lobes_.size() * width, 0.0);
    for (int j = 0; j < layout_.rows; ++j) {
      const double py = y + layout_.offsetY[j];
      for (int b = 0; b < blocks_; ++b) {
        if (active[lobes_.size() * blocks_ + b]) normals.compute(py, sampleBegin(b), sampleEnd(b));
      }
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        for (int b = 0; b < blocks_; ++b) {
          if (!active[k * blocks_ + b]) continue;
          distances(lobes_[k].axis, normals, sampleBegin(b), sampleEnd(b), u.get());
          const RadialTable::View table = lobes_[k].table.view();
          double* out = &lobeSums[k * width];
          for (int x = b * kBlock; x < std::min(width, (b + 1) * kBlock); ++x) {
            double acc = 0.0;
            for (int i = 0; i < columns; ++i) acc += table(u[x * columns + i]);
            out[x] += acc;
          }
        }
      }
    }
    const std::vector<int> counted(width, layout_.rows * columns);
    writeLobeRow(image, y, lobes_, lobeSums, counted, rowCoverage(map_, y));
  }

 private:
  int sampleBegin(int block) const { return block * kBlock * layout_.columns; }
  int sampleEnd(int block) const { return std::min(layout_.width, (block + 1) * kBlock) * layout_.columns; }

  /// u = |r - a| / 2 for samples [begin, end), r = (2 n_z n_x, 2 n_z n_y, 2 n_z^2 - 1).
  static void distances(const Vec3& axis, const SphereNormalRow& normals, int begin, int end, double* __restrict u) {
    const double ax = axis.x(), ay = axis.y(), az = axis.z();
    const double* __restrict nx = normals.x();
    const double* __restrict ny = normals.y();
    const double* __restrict nz = normals.z();
    for (int s = begin; s < end; ++s) {
      const double twoNz = 2.0 * nz[s];
      const double ex = twoNz * nx[s] - ax, ey = twoNz * ny[s] - ay, ez = twoNz * nz[s] - 1.0 - az;
      u[s] = 0.5 * std::sqrt(ex * ex + ey * ey + ez * ez);
    }
  }

  /// active[k * blocks + b]: lobe k may be non-zero somewhere in block b of row y (texels
  /// [b kBlock, (b + 1) kBlock)); active[lobes * blocks + b]: some lobe may. Blocks reaching the
  /// rim are never culled. Inside the disc the block's normals lie within the chord c of its
  /// centre's normal found at its corners (n.n_c is concave over the block's rectangle, so its
  /// minimum is at a corner), i.e. within the angle 2 asin(c / 2); reflection doubles angles at
  /// most (ds_r^2 = 4 dtheta^2 + sin^2(2 theta) dphi^2 <= 4 ds_n^2), so every sample's angle to
  /// the axis is within twice that of the centre's. A lobe is culled when that interval misses
  /// its support [2 asin(minU), 2 asin(maxU)]. Blocks at and beyond the rim use a second bound:
  /// a normal at disc radius rho reflects to polar angle 2 asin(rho) from +z, so every sample's r
  /// lies within pi - 2 asin(rho_min) of -z (rho_min: the block's nearest point to the centre;
  /// samples pulled in at the rim are within 1e-7 of -z).
  std::vector<unsigned char> cullBlocks(int y) const {
    constexpr double kRim2 = (1.0 - 1e-15) * (1.0 - 1e-15);
    const std::size_t lobeCount = lobes_.size();
    std::vector<unsigned char> active((lobeCount + 1) * blocks_, 0);
    const double top = 1.0 - y * twoOverN_, bottom = 1.0 - (y + 1) * twoOverN_, middle = 0.5 * (top + bottom);
    for (int b = 0; b < blocks_; ++b) {
      const double left = b * kBlock * twoOverN_ - 1.0;
      const double right = std::min(layout_.width, (b + 1) * kBlock) * twoOverN_ - 1.0;
      const double far = std::max(left * left, right * right) + std::max(top * top, bottom * bottom);
      const Vec3 centre = discNormal(0.5 * (left + right), middle);
      double spread = std::numeric_limits<double>::infinity();
      if (far < kRim2) {
        double chord2 = 0.0;
        for (const double cx : {left, right})
          for (const double cy : {top, bottom}) chord2 = std::max(chord2, (discNormal(cx, cy) - centre).squaredNorm());
        spread = 4.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(chord2))) + 1e-9;
      }
      const Vec3 reflected(2.0 * centre.z() * centre.x(), 2.0 * centre.z() * centre.y(),
                           2.0 * centre.z() * centre.z() - 1.0);
      const double nearX = std::clamp(0.0, left, right), nearY = std::clamp(0.0, bottom, top);
      const double cap = kPi - 2.0 * std::asin(std::min(1.0, std::sqrt(nearX * nearX + nearY * nearY))) + 1e-6;
      bool any = false;
      for (std::size_t k = 0; k < lobeCount; ++k) {
        const LobeSupport& support = supports_[k];
        if (!support.sampled) continue;
        const double angle = angleBetween(reflected, lobes_[k].axis);
        const double lo = std::max(angle - spread, support.fromBack - cap);
        const double hi = std::min(angle + spread, support.fromBack + cap);
        const bool on = lo <= support.maxAngle && hi >= support.minAngle;
        active[k * blocks_ + b] = on;
        any = any || on;
      }
      active[lobeCount * blocks_ + b] = any;
    }
    return active;
  }

  /// Angle between unit vectors, accurate near 0: 2 asin(|a - b| / 2).
  static double angleBetween(const Vec3& a, const Vec3& b) {
    return 2.0 * std::asin(std::min(1.0, 0.5 * (a - b).norm()));
  }
  static Vec3 discNormal(double x, double y) { return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))}; }

  /// A lobe's support as angles from its axis, and the angle from its axis to -z (radians).
  struct LobeSupport {
    bool sampled;  // not a delta lobe, not zero everywhere
    double minAngle, maxAngle, fromBack;
  };

  const Parameterization& map_;
  const std::vector<TabulatedLobe>& lobes_;
  const SampleLayout& layout_;
  double twoOverN_;
  int blocks_;
  std::vector<LobeSupport> supports_;
};

// ---------------------------------------------------------------------------------------------
// Microfacet path: Cook-Torrance lobes (one per light) through n = normalize(r + v), with h, v.h
// and F(v.h) fixed per light; D tabulated once per light over u = |n - h| / 2.

struct TabulatedMicrofacetLobe {
  Vec3 light, half;
  double viewDotHalf;
  Rgb specular, diffuse;
  RadialTable distribution;
};

std::vector<TabulatedMicrofacetLobe> tabulateMicrofacetLobes(const std::vector<MicrofacetLobe>& lobes,
                                                             const BakeOptions& options) {
  std::vector<TabulatedMicrofacetLobe> tables;
  for (const auto& lobe : lobes) {
    tables.push_back({lobe.light, lobe.halfVector, lobe.viewDotHalf, lobe.specular, lobe.diffuse,
                      RadialTable(lobe.distribution, options.profileTolerance)});
  }
  return tables;
}

class MicrofacetPath final : public RowPath {
 public:
  MicrofacetPath(const Parameterization& map, const MapFunction& function, const Vec3& view,
                 const std::vector<TabulatedMicrofacetLobe>& lobes, const SampleLayout& layout)
      : map_(map), function_(function), view_(view), lobes_(lobes), layout_(layout) {}

  void bakeRow(int y, Image& image) const override {
    const int width = layout_.width;
    SampleRow row(layout_);
    const std::vector<unsigned char> all(width, 1);
    std::vector<double> inverseNorm(layout_.rowSamples());
    std::vector<double> lobeSums(2 * lobes_.size() * width, 0.0);  // [lobe][specular, diffuse][texel]
    std::vector<Rgb> sums(width, Rgb::Zero());                     // samples at the rim, through the model
    for (int j = 0; j < layout_.rows; ++j) {
      mapSampleRow(map_, layout_, y + layout_.offsetY[j], all, row);
      normalsOf(row, inverseNorm, sums);
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        accumulate(lobes_[k], row, inverseNorm, &lobeSums[2 * k * width], &lobeSums[(2 * k + 1) * width]);
      }
    }
    for (int x = 0; x < width; ++x) {
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        sums[x] +=
            lobes_[k].specular * lobeSums[2 * k * width + x] + lobes_[k].diffuse * lobeSums[(2 * k + 1) * width + x];
      }
    }
    writeRow(image, y, sums, row.counted, rowCoverage(map_, y));
  }

 private:
  /// 1 / |r + v| per sample, or 0 for invalid samples and for r = -v (where the normal is not
  /// r + v: those samples are evaluated through the model and added to rim[x] instead).
  void normalsOf(const SampleRow& row, std::vector<double>& inverseNorm, std::vector<Rgb>& rim) const {
    const double vx = view_.x(), vy = view_.y(), vz = view_.z();
    for (int s = 0; s < layout_.rowSamples(); ++s) {
      const double sx = row.x[s] + vx, sy = row.y[s] + vy, sz = row.z[s] + vz;
      const double norm = std::sqrt(sx * sx + sy * sy + sz * sz);
      const bool normal = norm > 1e-12;  // geometryForReflection's threshold
      inverseNorm[s] = row.valid[s] && normal ? 1.0 / norm : 0.0;
      if (row.valid[s] && !normal) rim[s / layout_.columns] += function_.evaluate(Vec3(row.x[s], row.y[s], row.z[s]));
    }
  }

  /// Adds D G n.l (into specular[x]) and n.l (into diffuse[x]) over the row's samples of each texel.
  void accumulate(const TabulatedMicrofacetLobe& lobe, const SampleRow& row, const std::vector<double>& inverseNorm,
                  double* specular, double* diffuse) const {
    const RadialTable::View table = lobe.distribution.view();
    const double vx = view_.x(), vy = view_.y(), vz = view_.z();  // v is unit
    const double lx = lobe.light.x(), ly = lobe.light.y(), lz = lobe.light.z();
    const double hx = lobe.half.x(), hy = lobe.half.y(), hz = lobe.half.z();
    const double twoOverVh = 2.0 / lobe.viewDotHalf;
    const int columns = layout_.columns;
    for (int x = 0; x < layout_.width; ++x) {
      double specularSum = 0.0, diffuseSum = 0.0;
      for (int s = x * columns; s < (x + 1) * columns; ++s) {
        const double w = inverseNorm[s];
        const double nx = (row.x[s] + vx) * w, ny = (row.y[s] + vy) * w, nz = (row.z[s] + vz) * w;
        const double nl = nx * lx + ny * ly + nz * lz;
        const double nh = nx * hx + ny * hy + nz * hz;
        const double ex = nx - hx, ey = ny - hy, ez = nz - hz;
        const double d = table(0.5 * std::sqrt(ex * ex + ey * ey + ez * ez));
        // cookTorranceGOverNlNv for nl > 0, nv > 0, nh > 0, vh > 0, times n.l, without divisions:
        // n.v = (1 + r.v) / |r + v| = |r + v| / 2, so 1 / n.v = 2 w, and
        // min(1 / nv, x nl / max(nl, nv)) = min(1 / nv, x min(1, nl / nv)), x = 2 nh / vh.
        const double inverseNv = 2.0 * w;
        const double masked = twoOverVh * nh * std::min(1.0, nl * inverseNv);
        const double gNl = std::min(inverseNv, masked);
        const bool lit = nl > 0.0 && w > 0.0;
        specularSum += lit && nh > 0.0 ? d * gNl : 0.0;
        diffuseSum += lit ? nl : 0.0;
      }
      specular[x] += specularSum;
      diffuse[x] += diffuseSum;
    }
  }

  const Parameterization& map_;
  const MapFunction& function_;
  Vec3 view_;
  const std::vector<TabulatedMicrofacetLobe>& lobes_;
  const SampleLayout& layout_;
};

/// The microfacet path on a sphere map seen along its own axis (v = +z): the normal of a sample
/// is its disc position (SphereNormalRow), so no direction is mapped and n.v = n_z.
class SphereMicrofacetPath final : public RowPath {
 public:
  SphereMicrofacetPath(const Parameterization& map, const std::vector<TabulatedMicrofacetLobe>& lobes,
                       const SampleLayout& layout)
      : map_(map), lobes_(lobes), layout_(layout) {}

  void bakeRow(int y, Image& image) const override {
    const int width = layout_.width, columns = layout_.columns;
    SphereNormalRow normals(map_, layout_, true);
    const auto specular = SphereNormalRow::scratch(layout_.rowSamples()),
               diffuse = SphereNormalRow::scratch(layout_.rowSamples()),
               u = SphereNormalRow::scratch(layout_.rowSamples());
    std::vector<double> lobeSums(2 * lobes_.size() * width, 0.0);  // [lobe][specular, diffuse][texel]
    for (int j = 0; j < layout_.rows; ++j) {
      normals.compute(y + layout_.offsetY[j]);
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        shade(lobes_[k], normals, specular.get(), diffuse.get(), u.get());
        addTexelSums(specular.get(), width, columns, &lobeSums[2 * k * width]);
        addTexelSums(diffuse.get(), width, columns, &lobeSums[(2 * k + 1) * width]);
      }
    }
    std::vector<Rgb> sums(width, Rgb::Zero());
    for (int x = 0; x < width; ++x) {
      for (std::size_t k = 0; k < lobes_.size(); ++k) {
        sums[x] +=
            lobes_[k].specular * lobeSums[2 * k * width + x] + lobes_[k].diffuse * lobeSums[(2 * k + 1) * width + x];
      }
    }
    const std::vector<int> counted(width, layout_.rows * columns);
    writeRow(image, y, sums, counted, rowCoverage(map_, y));
  }

 private:
  /// D G n.l (specular[s]) and n.l (diffuse[s]) of every sample of the row, as MicrofacetPath
  /// with 1 / n.v = 1 / n_z and |n - h| / 2 = sqrt((1 - n.h) / 2) (into u[s]): a branch-free
  /// loop, then the table lookups where G n.l is not zero.
  void shade(const TabulatedMicrofacetLobe& lobe, const SphereNormalRow& normals, double* __restrict specular,
             double* __restrict diffuse, double* __restrict u) const {
    const double lx = lobe.light.x(), ly = lobe.light.y(), lz = lobe.light.z();
    const double hx = lobe.half.x(), hy = lobe.half.y(), hz = lobe.half.z();
    const double twoOverVh = 2.0 / lobe.viewDotHalf;
    const double* __restrict nx = normals.x();
    const double* __restrict ny = normals.y();
    const double* __restrict nz = normals.z();
    const double* __restrict inverseNv = normals.inverseZ();
    const int count = layout_.rowSamples();
    for (int s = 0; s < count; ++s) {
      const double nl = nx[s] * lx + ny[s] * ly + nz[s] * lz;
      const double nh = nx[s] * hx + ny[s] * hy + nz[s] * hz;
      const double masked = twoOverVh * nh * std::min(1.0, nl * inverseNv[s]);
      const double gNl = std::min(inverseNv[s], masked);
      const double frontGNl = nh > 0.0 ? gNl : 0.0;
      specular[s] = nl > 0.0 ? frontGNl : 0.0;
      diffuse[s] = nl > 0.0 ? nl : 0.0;
      u[s] = std::sqrt(std::max(0.0, 0.5 - 0.5 * nh));
    }
    const RadialTable::View table = lobe.distribution.view();
    for (int s = 0; s < count; ++s) {
      if (specular[s] != 0.0) specular[s] *= table(u[s]);
    }
  }

  const Parameterization& map_;
  const std::vector<TabulatedMicrofacetLobe>& lobes_;
  const SampleLayout& layout_;
};

/// Deposits the delta lobes: a box of half-width = the lobe's half-energy angle, in pixels, around
/// the axis' address, split among the texels it overlaps (within the axis' region). Returns how many.
int depositDeltaLobes(const Parameterization& map, const std::vector<TabulatedLobe>& lobes, Image& image) {
  int deltas = 0;
  for (const auto& lobe : lobes) {
    if (!lobe.delta) continue;
    ++deltas;
    const MapAddress at = map.getAddressFor(lobe.axis);
    const TexelRect rect = map.region(at.region);
    const double density = std::max(map.solidAngleDensity(at.pixel), 1e-300);  // sr per pixel^2
    const double half = std::clamp(lobe.table.halfEnergyAngle() / std::sqrt(density), 1e-6, 0.5);
    const double x0 = std::clamp(at.pixel.x() - half, double(rect.x0), double(rect.x0 + rect.width) - 2 * half);
    const double y0 = std::clamp(at.pixel.y() - half, double(rect.y0), double(rect.y0 + rect.height) - 2 * half);
    const double x1 = x0 + 2 * half, y1 = y0 + 2 * half, area = 4 * half * half;
    for (int ty = static_cast<int>(std::floor(y0)); ty < static_cast<int>(std::ceil(y1)); ++ty) {
      for (int tx = static_cast<int>(std::floor(x0)); tx < static_cast<int>(std::ceil(x1)); ++tx) {
        const double overlap =
            (std::min(x1, tx + 1.0) - std::max(x0, double(tx))) * (std::min(y1, ty + 1.0) - std::max(y0, double(ty)));
        const double solidAngle = map.texelSolidAngle(tx, ty);
        if (overlap <= 0.0 || solidAngle <= 0.0) continue;
        const Rgb add = lobe.weight * (lobe.table.energy() * overlap / area / solidAngle);
        const Rgba old = image.at(tx, ty);
        image.set(tx, ty, Rgba(old[0] + add[0], old[1] + add[1], old[2] + add[2], old[3]));
      }
    }
  }
  return deltas;
}

// ---------------------------------------------------------------------------------------------
// Running a path over the rows, and the summary.

void bakeRows(const Parameterization& map, const RowPath& path, const BakeOptions& options, Image& image) {
  ProgressCounter progress(options.progress, static_cast<std::size_t>(map.height()));
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, map.height()), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) {
        path.bakeRow(y, image);
        progress.step();
      }
    });
  });
}

void describeLobes(const std::vector<TabulatedLobe>& lobes, BakeSummary& summary) {
  summary.lobes = static_cast<int>(lobes.size());
  for (const auto& lobe : lobes) {
    summary.largestTable = std::max(summary.largestTable, lobe.table.size());
    summary.tableError = std::max(summary.tableError, lobe.table.relativeError());
  }
}

}  // namespace

void BakeOptions::validate() const {
  require(samplesPerTexel >= 1 && samplesPerTexel <= 4096,
          "samples_per_texel must be in [1, 4096], got " + std::to_string(samplesPerTexel));
  validateRun();
  require(profileTolerance > 0.0 && profileTolerance < 1.0, "profile tolerance must be in (0, 1)");
}

std::string BakeSummary::briefReport() const {
  std::ostringstream out;
  out << "path " << path << ", " << samples << " samples in " << seconds << " s";
  if (lobes > 0)
    out << ", " << lobes << " tabulated lobes (largest " << largestTable << " entries, error " << tableError << ")";
  return out.str();
}

BakedMap bakeMap(const Parameterization& map, const MapFunction& function, const BakeOptions& options) {
  options.validate();
  options.requireImageSize(map.width(), map.height());
  const auto start = std::chrono::steady_clock::now();
  BakedMap result{Image(map.width(), map.height()), BakeSummary{}};
  BakeSummary& summary = result.summary;
  const SampleLayout layout(options.samplesPerTexel, map.width());

  if (const auto radial = function.radialLobes()) {
    const std::vector<TabulatedLobe> lobes = tabulateLobes(*radial, map, options);
    if (allAboutViewAxis(map, lobes)) {
      summary.path = "radial-view-axis";
      bakeRows(map, ViewAxisPath(map, lobes, layout), options, result.image);
    } else if (map.kind() == ParameterizationKind::Sphere) {
      summary.path = "radial";
      bakeRows(map, SphereRadialPath(map, lobes, layout), options, result.image);
    } else {
      summary.path = "radial";
      bakeRows(map, RadialPath(map, lobes, layout), options, result.image);
    }
    summary.deltaLobes = depositDeltaLobes(map, lobes, result.image);
    describeLobes(lobes, summary);
  } else if (const auto microfacet = function.microfacetLobes(); microfacet && !microfacet->empty()) {
    const std::vector<TabulatedMicrofacetLobe> lobes = tabulateMicrofacetLobes(*microfacet, options);
    summary.path = "microfacet";
    const Vec3& view = microfacet->front().view;
    if (map.kind() == ParameterizationKind::Sphere && (view - Vec3::UnitZ()).squaredNorm() < 1e-30) {
      bakeRows(map, SphereMicrofacetPath(map, lobes, layout), options, result.image);
    } else {
      bakeRows(map, MicrofacetPath(map, function, view, lobes, layout), options, result.image);
    }
    summary.lobes = static_cast<int>(lobes.size());
    for (const auto& lobe : lobes) {
      summary.largestTable = std::max(summary.largestTable, lobe.distribution.size());
      summary.tableError = std::max(summary.tableError, lobe.distribution.relativeError());
    }
  } else {
    summary.path = "general";
    bakeRows(map, GeneralPath(map, function, layout), options, result.image);
  }

  summary.samples = static_cast<long long>(map.width()) * map.height() * options.samplesPerTexel;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

Rgb bakeTexel(const Parameterization& map, const MapFunction& function, int x, int y, int samplesPerTexel) {
  // The general path's samples, mapped the same way (getDirectionsForRow), for the same values.
  const int rows = gridRows(samplesPerTexel), columns = samplesPerTexel / rows;
  thread_local std::vector<double> px, dx, dy, dz;  // reused: a texel at a time is the caller's hot loop
  thread_local std::vector<unsigned char> valid;
  for (auto* v : {&px, &dx, &dy, &dz}) v->resize(columns);
  valid.resize(columns);
  for (int i = 0; i < columns; ++i) px[i] = x + (i + 0.5) / columns;
  Rgb sum = Rgb::Zero();
  int counted = 0;
  for (int j = 0; j < rows; ++j) {
    map.getDirectionsForRow(y + (j + 0.5) / rows, px.data(), columns, dx.data(), dy.data(), dz.data(), valid.data());
    for (int i = 0; i < columns; ++i) {
      if (!valid[i]) continue;
      sum += function.evaluate(Vec3(dx[i], dy[i], dz[i]));
      ++counted;
    }
  }
  return counted > 0 ? Rgb(sum / counted) : Rgb::Zero();
}

Image bake(const Parameterization& map, const MapFunction& function, const BakeOptions& options) {
  return bakeMap(map, function, options).image;
}

}  // namespace brdfbake
