#pragma once
// What the prefilter benches share (bench/prefilter_bench.cpp, bench/ibl_bench.cpp): wall-clock
// timing, an environment written for cmgen, cmgen's texel directions, and finding other tools.
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake::bench {

using Clock = std::chrono::steady_clock;

/// Wall-clock seconds since `start`.
inline double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// The environment's RGB as a 3-channel float EXR (what cmgen and cmft read).
inline void writeFloatRgbExr(const Environment& environment, const std::filesystem::path& path) {
  const Image& image = environment.image;
  std::vector<float> rgb(static_cast<std::size_t>(image.width()) * image.height() * 3);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c)
        rgb[(static_cast<std::size_t>(y) * image.width() + x) * 3 + c] = image.data()[image.index(x, y) + c];
  auto out = OIIO::ImageOutput::create(path.string());
  OIIO::ImageSpec spec(image.width(), image.height(), 3, OIIO::TypeDesc::FLOAT);
  if (!out || !out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) ||
      !out->close()) {
    throw Error(Error::Kind::Io, path.string() + ": cannot write");
  }
}

/// cmgen's face F texel (x, y) of an n^2 face, in brdfbake's frame: cmgen's face F holds the
/// OpenGL face F of the frame (x, y, -z) (found with a direction-coded environment).
inline Vec3 cmgenDirection(int face, int x, int y, int n) {
  const Vec3 c = CubeMap::faceDirection(static_cast<CubeMap::Face>(face), Vec2((x + 0.5) / n, (y + 0.5) / n));
  return {c.x(), c.y(), -c.z()};
}

/// Whether `name` is a program on the PATH.
inline bool haveProgram(const std::string& name) {
  return std::system(("command -v " + name + " > /dev/null 2>&1").c_str()) == 0;
}

}  // namespace brdfbake::bench
