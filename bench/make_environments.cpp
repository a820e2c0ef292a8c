// Writes the generated test environments of data_samples/environments/ (docs/prefilter.md):
//
//   build/bench/make_environments data_samples/environments [ROWS]
//
// furnace_latlong.exr (L = 1 everywhere), sky_latlong.exr (sky, aureole, ground and a 1.5 degree
// sun of radiance ~2000), colored_cube_latlong.exr (Heidrich 2000 Fig. 1) as 2N x N lat-long images
// (N = ROWS, default 128), and colored_cube_cross.exr as a 4N/2 x 3N/2 cube cross. The files are
// plain images (no brdfbake metadata), so `prefilter` reads them by their aspect ratio.
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/image_io.hpp>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  using namespace brdfbake;
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: make_environments OUTPUT_DIR [ROWS]\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const int rows = argc == 3 ? std::stoi(argv[2]) : 128;
  try {
    auto write = [&](const MapFunction& function, ParameterizationKind kind, int resolution, const std::string& name) {
      Environment environment = bakeEnvironment(function, kind, resolution, name, 64);
      environment.image.metadata = nlohmann::json::object();  // a plain environment image
      writeImage(environment.image, dir / name);
      std::cout << "wrote " << (dir / name).string() << " (" << environment.image.width() << " x "
                << environment.image.height() << ")\n";
    };
    write(ConstantEnvironment(), ParameterizationKind::LatLong, rows, "furnace_latlong.exr");
    write(SkyEnvironment(), ParameterizationKind::LatLong, rows, "sky_latlong.exr");
    write(ColoredCubeEnvironment(), ParameterizationKind::LatLong, rows, "colored_cube_latlong.exr");
    write(ColoredCubeEnvironment(), ParameterizationKind::Cube, rows / 2, "colored_cube_cross.exr");
  } catch (const Error& e) {
    std::cerr << "make_environments: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
