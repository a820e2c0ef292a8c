#include <brdfbake/core/error.hpp>
#include <brdfbake/core/run_options.hpp>

#include <sstream>
#include <string>

namespace brdfbake {

void requireThreadCount(int threads, const std::string& what) {
  require(threads >= 0 && threads <= kMaxThreads, what + " must be in [0, " + std::to_string(kMaxThreads) +
                                                      "] (0 = every core), got " + std::to_string(threads));
}

void RunOptions::validateRun() const {
  requireThreadCount(threads);
  require(maxTexels > 0, "maxTexels must be > 0");
}

void RunOptions::requireImageSize(int width, int height) const {
  const long long texels = static_cast<long long>(width) * height;
  if (texels <= maxTexels || allowLarge) return;
  std::ostringstream message;
  message << "a " << width << " x " << height << " map needs " << static_cast<double>(texels) * 16.0 / (1u << 30)
          << " GiB of float RGBA, more than the limit of " << static_cast<double>(maxTexels) * 16.0 / (1u << 30)
          << " GiB; lower the resolution or allow large maps (--allow-large)";
  throw Error(Error::Kind::Resource, message.str());
}

}  // namespace brdfbake
