#include <brdfbake/core/error.hpp>
#include <brdfbake/run/job.hpp>

namespace brdfbake {

nlohmann::json pathsToJson(const std::vector<std::filesystem::path>& paths) {
  nlohmann::json array = nlohmann::json::array();
  for (const auto& path : paths) array.push_back(path.string());
  return array;
}

}  // namespace brdfbake
