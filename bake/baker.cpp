#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/maps/radial_table.hpp>

#include "row_paths.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <limits>
#include <memory>
#include <sstream>

namespace brdfbake {
using namespace bake_detail;
namespace {

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
// Running a path over the rows, and the summary.

void bakeRows(const Parameterization& map, const RowPath& path, const Context& context, Image& image) {
  ProgressCounter progress(context.progress(), static_cast<std::size_t>(map.height()));
  tbb::task_arena arena(context.arenaThreads());
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
  require(profileTolerance > 0.0 && profileTolerance < 1.0, "profile tolerance must be in (0, 1)");
}

std::string BakeSummary::briefReport() const {
  std::ostringstream out;
  out << "path " << path << ", " << samples << " samples in " << seconds << " s";
  if (lobes > 0)
    out << ", " << lobes << " tabulated lobes (largest " << largestTable << " entries, error " << tableError << ")";
  return out.str();
}

BakedMap bakeMap(const Parameterization& map, const MapFunction& function, const BakeOptions& options,
                 const Context& context) {
  options.validate();
  context.requireImageSize(map.width(), map.height());
  const auto start = std::chrono::steady_clock::now();
  BakedMap result{Image(map.width(), map.height()), BakeSummary{}};
  BakeSummary& summary = result.summary;
  const SampleLayout layout(options.samplesPerTexel, map.width());

  if (const auto radial = function.radialLobes()) {
    const std::vector<TabulatedLobe> lobes = tabulateLobes(*radial, map, options);
    if (allAboutViewAxis(map, lobes)) {
      summary.path = "radial-view-axis";
      bakeRows(map, *makeViewAxisPath(map, lobes, layout), context, result.image);
    } else if (map.kind() == ParameterizationKind::Sphere) {
      summary.path = "radial";
      bakeRows(map, *makeSphereRadialPath(map, lobes, layout), context, result.image);
    } else {
      summary.path = "radial";
      bakeRows(map, *makeRadialPath(map, lobes, layout), context, result.image);
    }
    summary.deltaLobes = depositDeltaLobes(map, lobes, result.image);
    describeLobes(lobes, summary);
  } else if (const auto microfacet = function.microfacetLobes(); microfacet && !microfacet->empty()) {
    const std::vector<TabulatedMicrofacetLobe> lobes = tabulateMicrofacetLobes(*microfacet, options);
    summary.path = "microfacet";
    const Vec3& view = microfacet->front().view;
    if (map.kind() == ParameterizationKind::Sphere && (view - Vec3::UnitZ()).squaredNorm() < 1e-30) {
      bakeRows(map, *makeSphereMicrofacetPath(map, lobes, layout), context, result.image);
    } else {
      bakeRows(map, *makeMicrofacetPath(map, function, view, lobes, layout), context, result.image);
    }
    summary.lobes = static_cast<int>(lobes.size());
    for (const auto& lobe : lobes) {
      summary.largestTable = std::max(summary.largestTable, lobe.distribution.size());
      summary.tableError = std::max(summary.tableError, lobe.distribution.relativeError());
    }
  } else {
    summary.path = "general";
    bakeRows(map, GeneralPath(map, function, layout), context, result.image);
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

Image bake(const Parameterization& map, const MapFunction& function, const BakeOptions& options,
           const Context& context) {
  return bakeMap(map, function, options, context).image;
}

}  // namespace brdfbake
