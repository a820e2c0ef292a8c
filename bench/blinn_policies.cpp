// How far each Blinn-Phong conversion policy is from the Phong lobe it stands in for: max and RMS
// difference (the peak is 1) over a sphere map (eye space, every reflected direction equally
// weighted: the map is equal-area), for n = 1, 10, 100, 1000, with the light at the eye and with
// a light 45 degrees off the view axis. Prints the markdown table of docs/blinn_conversion.md.
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <cstdio>

int main() {
  using namespace brdfbake;
  const int n = 1024;
  const SphereMap map(n);
  struct Light {
    const char* name;
    Vec3 direction;
  };
  const Light lights[] = {{"eye (0, 0, 1)", Vec3::UnitZ()}, {"45 deg (1, 0, 1)", Vec3(1, 0, 1).normalized()}};
  std::printf(
      "| light | Phong n | policy | Blinn exponent | max difference | RMS difference |\n|---|---|---|---|---|---|\n");
  for (const Light& light : lights) {
    for (double exponent : {1.0, 10.0, 100.0, 1000.0}) {
      const PhongMaterial phong(Rgb::Ones(), exponent);
      for (BlinnConversion policy : {BlinnConversion::Exact, BlinnConversion::FourN, BlinnConversion::Fit}) {
        const BlinnPhongMaterial blinn(Rgb::Ones(), exponent, policy);
        double worst = 0.0, sum = 0.0;
        long count = 0;
        for (int y = 0; y < n; ++y) {
          for (int x = 0; x < n; ++x) {
            if (map.texelCoverage(x, y) < 1.0) continue;
            const Vec3 r = *map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
            const ShadingGeometry g = geometryForReflection(r, Vec3::UnitZ());
            const double d = blinn.shade(g, light.direction)[0] - phong.shade(g, light.direction)[0];
            worst = std::max(worst, std::abs(d));
            sum += d * d;
            ++count;
          }
        }
        char exponentText[32];
        if (policy == BlinnConversion::Exact)
          std::snprintf(exponentText, sizeof exponentText, "per texel");
        else
          std::snprintf(exponentText, sizeof exponentText, "%.4g", blinn.exponent());
        std::printf("| %s | %g | %s | %s | %.4f | %.5f |\n", light.name, exponent,
                    std::string(toString(policy)).c_str(), exponentText, worst, std::sqrt(sum / count));
      }
    }
  }
  return 0;
}
