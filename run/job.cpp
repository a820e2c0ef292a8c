#include <brdfbake/core/error.hpp>
#include <brdfbake/run/job.hpp>

namespace brdfbake {

void JobOptions::validate() const {
  require(threads >= 0 && threads <= kMaxThreads, "threads must be in [0, " + std::to_string(kMaxThreads) +
                                                      "] (0 = every core), got " + std::to_string(threads));
}

nlohmann::json pathsToJson(const std::vector<std::filesystem::path>& paths) {
  nlohmann::json array = nlohmann::json::array();
  for (const auto& path : paths) array.push_back(path.string());
  return array;
}

}  // namespace brdfbake
