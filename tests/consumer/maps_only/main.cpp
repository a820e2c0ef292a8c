// A renderer-side program linked against the installed brdfbake::maps alone: it fills a sphere map
// in memory with a known function of the reflected direction, looks it up as a GPU's bilinear filter
// does, and checks the lookups against the function; then checks that no OpenImageIO library is
// mapped into the process.
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

int main() {
  using namespace brdfbake;
  const SphereMap map(256);
  Image image(map.width(), map.height());
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x)
      if (const auto r = map.getDirectionFor(Vec2(x + 0.5, y + 0.5))) image.set(x, y, Rgba(1 + r->y(), 0, 0, 1));
  double worst = 0.0;
  for (const Vec3& r : {Vec3(0, 0, 1), Vec3(0.3, 0.5, 0.8), Vec3(-0.6, -0.2, 0.4), Vec3(0.1, 0.9, -0.2)}) {
    const Vec3 d = r.normalized();
    worst = std::max(worst, std::abs(sampleBilinear(image, map, d)[0] - (1 + d.y())));
  }
  if (worst > 0.01) {
    std::printf("a lookup is %g off\n", worst);
    return 1;
  }
  std::ifstream mapped("/proc/self/maps");
  for (std::string line; std::getline(mapped, line);) {
    if (line.find("OpenImageIO") != std::string::npos || line.find("brdfbake_io") != std::string::npos) {
      std::printf("mapped: %s\n", line.c_str());
      return 1;
    }
  }
  std::printf("consumer: ok (sphere map lookups within %g, no OpenImageIO)\n", worst);
  return 0;
}
