// A renderer-side program using the installed brdfbake package: bake a Phong sphere map, write
// it, read it back and check a lookup against the analytic value.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  using namespace brdfbake;
  const std::filesystem::path dir = argc > 1 ? argv[1] : ".";
  const SphereMap map(64);
  const MaterialMapFunction phong(std::make_shared<PhongMaterial>(Rgb::Ones(), 10.0), {{Vec3::UnitZ(), Rgb::Ones()}},
                                  Vec3::UnitZ());
  const Image image = bake(map, phong);
  MapInfo info{ParameterizationKind::Sphere, 64, kConventionVersion, {{"material", "phong"}}};
  writeMap(image, info, dir / "consumer.exr");
  const MapFile file = readMap(dir / "consumer.exr");
  const Vec3 r = Vec3(0.2, 0.1, 1.0).normalized();
  const double expected = std::pow(r.z(), 10.0);
  const double got = sampleBilinear(file.image, *file.parameterization, r)[0];
  std::printf("brdfbake %s: lookup %.5f, analytic %.5f\n", BRDFBAKE_VERSION_STRING, got, expected);
  if (std::abs(got - expected) > 0.01) return 1;
  std::printf("consumer: ok\n");
  return 0;
}
