#pragma once
// The yardstick the benchmarks report ratios against (issue baselines): a plain single-threaded loop
// over the texels of a 1024^2 sphere map and 16 stratified samples each, in double, evaluating a
// Phong lobe of exponent 50 about the light (1, 1, 1) through the inverse mapping. A ratio to it is
// comparable across machines and loads where seconds are not.
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <vector>

namespace brdfbake::bench {

/// One run of the loop into `out` (1024 * 1024 * 3 floats, red written).
inline void plainPhongLoop(std::vector<float>& out) {
  static const SphereMap map(1024);
  const Vec3 light = Vec3(1, 1, 1).normalized();
  out.resize(1024 * 1024 * 3);
  for (int y = 0; y < 1024; ++y) {
    for (int x = 0; x < 1024; ++x) {
      double sum = 0.0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const Vec3 r = *map.getDirectionFor(Vec2(x + (i + 0.5) / 4, y + (j + 0.5) / 4));
          sum += phongLobe(r.dot(light), 50.0);
        }
      out[(static_cast<std::size_t>(y) * 1024 + x) * 3] = static_cast<float>(sum / 16);
    }
  }
}

}  // namespace brdfbake::bench
