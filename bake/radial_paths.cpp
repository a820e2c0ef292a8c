// The radial paths of the baker: each lobe's profile tabulated once (RadialTable), looked up per sample.
#include "row_paths.hpp"

namespace brdfbake::bake_detail {

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

namespace {

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

}  // namespace

std::unique_ptr<RowPath> makeRadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                        const SampleLayout& layout) {
  return std::make_unique<RadialPath>(map, lobes, layout);
}

std::unique_ptr<RowPath> makeViewAxisPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                          const SampleLayout& layout) {
  return std::make_unique<ViewAxisPath>(map, lobes, layout);
}

std::unique_ptr<RowPath> makeSphereRadialPath(const Parameterization& map, const std::vector<TabulatedLobe>& lobes,
                                              const SampleLayout& layout) {
  return std::make_unique<SphereRadialPath>(map, lobes, layout);
}

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

}  // namespace brdfbake::bake_detail
