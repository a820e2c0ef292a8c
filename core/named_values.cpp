#include <brdfbake/core/named_values.hpp>

#include <algorithm>

namespace brdfbake {

namespace {

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::optional<std::string> closestName(std::string_view word, const std::vector<std::string>& candidates) {
  if (word.empty() || word.size() > 64) return std::nullopt;  // nothing to match, or not a mistyped name
  std::optional<std::string> best;
  std::size_t bestDistance = std::max<std::size_t>(2, word.size() / 3) + 1;
  std::vector<std::string> extending;
  for (const auto& candidate : candidates) {
    if (candidate.rfind(word, 0) == 0) extending.push_back(candidate);
    const std::size_t distance = editDistance(word, candidate);
    if (distance < bestDistance) bestDistance = distance, best = candidate;
  }
  if (!best && extending.size() == 1) best = extending.front();
  return best;
}

std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates) {
  const auto name = closestName(word, candidates);
  return name ? " (did you mean '" + *name + "'?)" : std::string();
}

}  // namespace brdfbake
