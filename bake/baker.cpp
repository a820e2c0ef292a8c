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

class Progress {
 public:
  Progress(const std::function<void(double)>& callback, int total) : callback_(callback), total_(total) {}
  void rowDone() {
    const int done = ++done_;
    if (!callback_) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (lock.owns_lock() || done == total_) {
      if (!lock.owns_lock()) lock.lock();
      callback_(static_cast<double>(done) / total_);
    }
  }

 private:
  const std::function<void(double)>& callback_;
  int total_;
  std::atomic<int> done_{0};
  std::mutex mutex_;
};

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
  const bool viewAxis = radial && map.kind() == ParameterizationKind::Sphere &&
                        std::all_of(lobes.begin(), lobes.end(), [](const TabulatedLobe& l) {
                          return (l.axis - Vec3::UnitZ()).squaredNorm() < 1e-30;
                        });

  Image image(map.width(), map.height());
  const Grid grid = stratification(options.samplesPerTexel);
  const double n = map.resolution();
  Progress progress(options.progress, map.height());

  auto bakeRow = [&](int y) {
    for (int x = 0; x < map.width(); ++x) {
      const double coverage = map.texelCoverage(x, y);
      Rgb sum = Rgb::Zero();
      int counted = 0;
      for (int j = 0; j < grid.rows; ++j) {
        for (int i = 0; i < grid.columns; ++i) {
          const Vec2 pixel(x + (i + 0.5) / grid.columns, y + (j + 0.5) / grid.rows);
          if (viewAxis) {
            const double sx = 2.0 * pixel.x() / n - 1.0, sy = 1.0 - 2.0 * pixel.y() / n;
            const double u = std::sqrt(sx * sx + sy * sy);  // = sin(theta/2) of r about +z
            for (const auto& lobe : lobes) sum += lobe.weight * lobe.table.atU(u);
            ++counted;
            continue;
          }
          const auto direction = map.getDirectionFor(pixel);
          if (!direction) continue;
          ++counted;
          if (radial) {
            for (const auto& lobe : lobes) sum += lobe.weight * lobe.table.atU(0.5 * (*direction - lobe.axis).norm());
          } else {
            sum += function.evaluate(*direction);
          }
        }
      }
      const Rgb mean = counted > 0 ? Rgb(sum / counted) : Rgb::Zero();
      image.set(x, y, Rgba(mean[0], mean[1], mean[2], coverage));
    }
    progress.rowDone();
  };

  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, map.height()), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) bakeRow(y);
    });
  });

  if (summary) {
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
