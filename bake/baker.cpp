#include <brdfbake/core/progress.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/radial_table.hpp>
#include <brdfbake/core/error.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <sstream>

namespace brdfbake {
namespace {

struct Grid {
  int columns, rows;
};
// The most nearly square a x b grid with a b = n.
Grid stratification(int n) {
  int a = static_cast<int>(std::sqrt(static_cast<double>(n)));
  while (n % a != 0) --a;
  return {n / a, a};
}


struct TabulatedLobe {
  Vec3 axis;
  Rgb weight;
  RadialTable table;
};

}  // namespace

void BakeOptions::validate() const {
  require(samplesPerTexel >= 1 && samplesPerTexel <= 4096,
          "samples_per_texel must be in [1, 4096], got " + std::to_string(samplesPerTexel));
  require(threads >= 0, "threads must be >= 0 (0 = all cores), got " + std::to_string(threads));
  require(profileTolerance > 0.0 && profileTolerance < 1.0, "profile tolerance must be in (0, 1)");
  require(maxTexels > 0, "maxTexels must be > 0");
}

std::string BakeSummary::briefReport() const {
  std::ostringstream out;
  out << "path " << path << ", " << samples << " samples in " << seconds << " s";
  if (lobes > 0) out << ", " << lobes << " tabulated lobes (largest " << largestTable << " entries, error " << tableError << ")";
  return out.str();
}

Image bake(const Parameterization& map, const MapFunction& function, const BakeOptions& options,
           BakeSummary* summary) {
  options.validate();
  const long long texels = static_cast<long long>(map.width()) * map.height();
  if (texels > options.maxTexels && !options.allowLarge) {
    std::ostringstream message;
    message << "a " << map.width() << " x " << map.height() << " map needs "
            << static_cast<double>(texels) * 16.0 / (1u << 30) << " GiB of float RGBA, more than the limit of "
            << static_cast<double>(options.maxTexels) * 16.0 / (1u << 30)
            << " GiB; lower the resolution or allow large maps (--allow-large)";
    throw Error(Error::Kind::Resource, message.str());
  }
  const auto start = std::chrono::steady_clock::now();

  std::vector<TabulatedLobe> lobes;
  const auto radial = function.radialLobes();
  if (radial) {
    for (const auto& lobe : *radial) {
      lobes.push_back({lobe.axis.normalized(), lobe.weight, RadialTable(lobe.profile, options.profileTolerance)});
    }
  }
  // Lobes narrower than the sample spacing around their axis are deposited, not sampled.
  std::vector<unsigned char> deltaLobe(lobes.size(), 0);
  {
    const double samplesPerTexel = options.samplesPerTexel;
    for (std::size_t k = 0; k < lobes.size(); ++k) {
      const MapAddress at = map.getAddressFor(lobes[k].axis);
      const TexelRect rect = map.region(at.region);
      const int tx = std::clamp(static_cast<int>(at.pixel.x()), rect.x0, rect.x0 + rect.width - 1);
      const int ty = std::clamp(static_cast<int>(at.pixel.y()), rect.y0, rect.y0 + rect.height - 1);
      const double texelAngle = std::sqrt(std::max(map.texelSolidAngle(tx, ty), 1e-300));
      const double spacing = texelAngle / std::sqrt(samplesPerTexel);
      deltaLobe[k] = 2.0 * lobes[k].table.halfEnergyAngle() < spacing && lobes[k].table.energy() != 0.0;
    }
  }
  const bool viewAxis = radial && map.kind() == ParameterizationKind::Sphere &&
                        std::all_of(lobes.begin(), lobes.end(), [](const TabulatedLobe& l) {
                          return (l.axis - Vec3::UnitZ()).squaredNorm() < 1e-30;
                        });

  Image image(map.width(), map.height());
  const Grid grid = stratification(options.samplesPerTexel);
  const double twoOverN = 2.0 / map.resolution();
  ProgressCounter progress(options.progress, static_cast<std::size_t>(map.height()));

  // Sample offsets inside a texel; rows of samples are mapped in batches (structure of arrays).
  std::vector<double> offsetX(grid.columns), offsetY(grid.rows);
  for (int i = 0; i < grid.columns; ++i) offsetX[i] = (i + 0.5) / grid.columns;
  for (int j = 0; j < grid.rows; ++j) offsetY[j] = (j + 0.5) / grid.rows;
  const int width = map.width();
  const int columns = grid.columns;
  const int rowSamples = width * columns;
  std::vector<double> samplePx(rowSamples);
  for (int x = 0; x < width; ++x)
    for (int i = 0; i < columns; ++i) samplePx[x * columns + i] = x + offsetX[i];
  const std::size_t lobeCount = lobes.size();

  // Culling: a texel contributes nothing to lobe k if every direction of its footprint lies
  // outside the table's support. Distances are chords |d - a| (a metric on the sphere, and
  // 2u for the table), so no trigonometry is needed: a texel's directions lie within `spread` of
  // its centre direction, estimated from its corners with a 1.5x margin for curvature; texels the
  // domain's boundary cuts through (0 < coverage < 1) are never culled.
  auto chord = [](double ax, double ay, double az, const Vec3& b) {
    return std::sqrt((ax - b.x()) * (ax - b.x()) + (ay - b.y()) * (ay - b.y()) + (az - b.z()) * (az - b.z()));
  };

  auto bakeRow = [&](int y) {
    std::vector<double> dx(rowSamples), dy(rowSamples), dz(rowSamples);
    std::vector<unsigned char> valid(rowSamples);
    std::vector<Rgb> sums(width, Rgb::Zero());
    std::vector<double> lobeSums(lobeCount * width, 0.0);  // [lobe][texel]
    std::vector<int> counted(width, 0);
    std::vector<double> coverage(width);
    for (int x = 0; x < width; ++x) coverage[x] = map.texelCoverage(x, y);

    // active[k * width + x]: lobe k may be non-zero somewhere in texel x. anyActive[x]: some lobe is.
    std::vector<unsigned char> active(lobeCount * width, 1), anyActive(width, 1);
    if (radial) {
      std::vector<double> cx(width + 1), cy(width + 1), cz(width + 1);
      std::vector<double> tx(width + 1), ty(width + 1), tz(width + 1), bx(width + 1), by(width + 1), bz(width + 1);
      std::vector<unsigned char> cv(width + 1), tv(width + 1), bv(width + 1);
      std::vector<double> edges(width + 1), centres(width);
      for (int x = 0; x <= width; ++x) edges[x] = x;
      for (int x = 0; x < width; ++x) centres[x] = x + 0.5;
      if (!viewAxis) {
        map.getDirectionsForRow(y + 0.5, centres.data(), width, cx.data(), cy.data(), cz.data(), cv.data());
        map.getDirectionsForRow(y, edges.data(), width + 1, tx.data(), ty.data(), tz.data(), tv.data());
        map.getDirectionsForRow(y + 1, edges.data(), width + 1, bx.data(), by.data(), bz.data(), bv.data());
      }
      for (int x = 0; x < width; ++x) {
        bool any = false;
        double lo = 0.0, hi = 0.0;  // range of u = chord / 2 of the texel's directions about a lobe axis
        double spread = 0.0;
        if (viewAxis) {
          // The radius in the unit disc is u about +z: its range over the texel's square.
          const double x0 = x * twoOverN - 1.0, x1 = (x + 1) * twoOverN - 1.0;
          const double y0 = 1.0 - (y + 1) * twoOverN, y1 = 1.0 - y * twoOverN;
          const double nearX = std::clamp(0.0, x0, x1), nearY = std::clamp(0.0, y0, y1);
          lo = std::min(1.0, std::sqrt(nearX * nearX + nearY * nearY));
          hi = std::min(1.0, std::sqrt(std::max(x0 * x0, x1 * x1) + std::max(y0 * y0, y1 * y1)));
        } else if (!cv[x]) {
          for (std::size_t k = 0; k < lobeCount; ++k) active[k * width + x] = 0;
          anyActive[x] = 0;
          continue;
        } else {
          const Vec3 centre(cx[x], cy[x], cz[x]);
          for (int c = 0; c < 2; ++c) {
            if (tv[x + c]) spread = std::max(spread, chord(tx[x + c], ty[x + c], tz[x + c], centre));
            if (bv[x + c]) spread = std::max(spread, chord(bx[x + c], by[x + c], bz[x + c], centre));
          }
          spread = 1.5 * spread + 1e-9;
        }
        const bool boundary = coverage[x] > 0.0 && coverage[x] < 1.0;
        for (std::size_t k = 0; k < lobeCount; ++k) {
          const RadialTable& table = lobes[k].table;
          if (deltaLobe[k]) {
            active[k * width + x] = 0;
            continue;
          }
          bool on = boundary && !viewAxis;
          if (!on) {
            if (!viewAxis) {
              const double distance = chord(cx[x], cy[x], cz[x], lobes[k].axis);
              lo = 0.5 * (distance - spread), hi = 0.5 * (distance + spread);
            }
            on = hi >= table.minU() && lo <= table.maxU();
          }
          active[k * width + x] = on;
          any = any || on;
        }
        anyActive[x] = any;
      }
    }

    for (int j = 0; j < grid.rows; ++j) {
      const double py = y + offsetY[j];
      if (viewAxis) {
        // u = sin(theta/2) of r about +z is the radius in the unit disc: no inverse mapping needed.
        const double sy = 1.0 - py * twoOverN;
        for (std::size_t k = 0; k < lobeCount; ++k) {
          const RadialTable::View table = lobes[k].table.view();
          double* out = &lobeSums[k * width];
          const double* px = samplePx.data();
          const unsigned char* on = &active[k * width];
          for (int x = 0; x < width; ++x) {
            if (!on[x]) continue;
            double acc = 0.0;
            for (int i = 0; i < columns; ++i) {
              const double sx = px[x * columns + i] * twoOverN - 1.0;
              acc += table(std::sqrt(sx * sx + sy * sy));
            }
            out[x] += acc;
          }
        }
        for (int x = 0; x < width; ++x) counted[x] += columns;
        continue;
      }
      // Map the samples of each run of texels that need them.
      for (int x0 = 0; x0 < width;) {
        if (!anyActive[x0]) {
          ++x0;
          continue;
        }
        int x1 = x0;
        while (x1 < width && anyActive[x1]) ++x1;
        const int first = x0 * columns, count = (x1 - x0) * columns;
        map.getDirectionsForRow(py, samplePx.data() + first, count, dx.data() + first, dy.data() + first,
                                dz.data() + first, valid.data() + first);
        for (int s = first; s < first + count; ++s) counted[s / columns] += valid[s];
        x0 = x1;
      }
      if (radial) {
        const double *X = dx.data(), *Y = dy.data(), *Z = dz.data();
        const unsigned char* ok = valid.data();
        for (std::size_t k = 0; k < lobeCount; ++k) {
          const RadialTable::View table = lobes[k].table.view();
          const double ax = lobes[k].axis.x(), ay = lobes[k].axis.y(), az = lobes[k].axis.z();
          double* out = &lobeSums[k * width];
          const unsigned char* on = &active[k * width];
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
      } else {
        for (int s = 0; s < rowSamples; ++s) {
          if (valid[s]) sums[s / columns] += function.evaluate(Vec3(dx[s], dy[s], dz[s]));
        }
      }
    }
    for (int x = 0; x < width; ++x) {
      Rgb sum = sums[x];
      // Lobe weights are per light and channel: applied once per texel, not per sample.
      for (std::size_t k = 0; k < lobeCount; ++k) sum += lobes[k].weight * lobeSums[k * width + x];
      const Rgb mean = counted[x] > 0 ? Rgb(sum / counted[x]) : Rgb::Zero();
      image.set(x, y, Rgba(mean[0], mean[1], mean[2], coverage[x]));
    }
    progress.step();
  };

  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, map.height()), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) bakeRow(y);
    });
  });

  // Deposit the delta lobes: a box of half-width = the lobe's half-energy angle, in pixels, around
  // the axis' address, split among the texels it overlaps (within the axis' region).
  int deltas = 0;
  for (std::size_t k = 0; k < lobes.size(); ++k) {
    if (!deltaLobe[k]) continue;
    ++deltas;
    const MapAddress at = map.getAddressFor(lobes[k].axis);
    const TexelRect rect = map.region(at.region);
    const double density = std::max(map.solidAngleDensity(at.pixel), 1e-300);  // sr per pixel^2
    const double half = std::clamp(lobes[k].table.halfEnergyAngle() / std::sqrt(density), 1e-6, 0.5);
    const double x0 = std::clamp(at.pixel.x() - half, double(rect.x0), double(rect.x0 + rect.width) - 2 * half);
    const double y0 = std::clamp(at.pixel.y() - half, double(rect.y0), double(rect.y0 + rect.height) - 2 * half);
    const double x1 = x0 + 2 * half, y1 = y0 + 2 * half, area = 4 * half * half;
    for (int ty = static_cast<int>(std::floor(y0)); ty < static_cast<int>(std::ceil(y1)); ++ty) {
      for (int tx = static_cast<int>(std::floor(x0)); tx < static_cast<int>(std::ceil(x1)); ++tx) {
        const double overlap = (std::min(x1, tx + 1.0) - std::max(x0, double(tx))) *
                               (std::min(y1, ty + 1.0) - std::max(y0, double(ty)));
        const double solidAngle = map.texelSolidAngle(tx, ty);
        if (overlap <= 0.0 || solidAngle <= 0.0) continue;
        const Rgb add = lobes[k].weight * (lobes[k].table.energy() * overlap / area / solidAngle);
        const Rgba old = image.at(tx, ty);
        image.set(tx, ty, Rgba(old[0] + add[0], old[1] + add[1], old[2] + add[2], old[3]));
      }
    }
  }

  if (summary) {
    summary->deltaLobes = deltas;
    summary->path = !radial ? "general" : (viewAxis ? "radial-view-axis" : "radial");
    summary->lobes = static_cast<int>(lobes.size());
    summary->largestTable = 0;
    summary->tableError = 0.0;
    for (const auto& lobe : lobes) {
      summary->largestTable = std::max(summary->largestTable, lobe.table.size());
      summary->tableError = std::max(summary->tableError, lobe.table.relativeError());
    }
    summary->samples = texels * options.samplesPerTexel;
    summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return image;
}

}  // namespace brdfbake
