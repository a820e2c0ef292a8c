// The whole installed package through <brdfbake/brdfbake.hpp>: read a measured table, fit one
// lobe, parse a spec that uses the fit, bake it, and check the fitted lobe's peak against the
// table's mirror sample.
#include <brdfbake/brdfbake.hpp>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  using namespace brdfbake;
  if (argc < 3) return 2;
  const std::filesystem::path table = argv[1], dir = argv[2];
  FitOptions options;
  options.lobes = 1;
  options.elevation = ElevationChoice::Constant;
  FitFile file;
  file.fit = fitLobes(readTableForFitting(table), options);
  if (!file.fit.usable()) return 1;
  writeFitFile(dir / "fit.json", file);
  const nlohmann::json spec = {{"maps",
                                {{{"output", "lobes.exr"},
                                  {"parameterization", "sphere"},
                                  {"resolution", 32},
                                  {"material", {{"model", "lobes"}, {"file", "fit.json"}}}}}}};
  const BakeSpec parsed = parseBakeSpec(spec, dir);
  const Image image = bake(*makeParameterization(ParameterizationKind::Sphere, 32), *parsed.maps[0].makeFunction());
  const Rgba centre = image.at(16, 16);
  std::printf("brdfbake %s: %zu lobe(s), centre texel %.4f\n", BRDFBAKE_VERSION_STRING,
              file.fit.model.channels[0].lobes.size(), centre[0]);
  if (!(centre[0] > 0.0f) || !allFinite(centre)) return 1;
  std::printf("consumer: ok\n");
  return 0;
}
