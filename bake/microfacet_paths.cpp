// The microfacet paths of the baker: Cook-Torrance lobes (one per light) through n = normalize(r + v),
// with h, v.h and F(v.h) fixed per light; D tabulated once per light over u = |n - h| / 2.
#include "row_paths.hpp"

namespace brdfbake::bake_detail {

std::vector<TabulatedMicrofacetLobe> tabulateMicrofacetLobes(const std::vector<MicrofacetLobe>& lobes,
                                                             const BakeOptions& options) {
  std::vector<TabulatedMicrofacetLobe> tables;
  for (const auto& lobe : lobes) {
    tables.push_back({lobe.light, lobe.halfVector, lobe.viewDotHalf, lobe.specular, lobe.diffuse,
                      RadialTable(lobe.distribution, options.profileTolerance)});
  }
  return tables;
}

namespace {

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

}  // namespace

std::unique_ptr<RowPath> makeMicrofacetPath(const Parameterization& map, const MapFunction& function, const Vec3& view,
                                            const std::vector<TabulatedMicrofacetLobe>& lobes,
                                            const SampleLayout& layout) {
  return std::make_unique<MicrofacetPath>(map, function, view, lobes, layout);
}

std::unique_ptr<RowPath> makeSphereMicrofacetPath(const Parameterization& map,
                                                  const std::vector<TabulatedMicrofacetLobe>& lobes,
                                                  const SampleLayout& layout) {
  return std::make_unique<SphereMicrofacetPath>(map, lobes, layout);
}

}  // namespace brdfbake::bake_detail
