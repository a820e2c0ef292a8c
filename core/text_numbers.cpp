#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/core/text_numbers.hpp>

#include <charconv>
#include <cmath>
#include <string>

namespace brdfbake {

namespace {

std::string_view trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  text.remove_prefix(first);
  text.remove_suffix(text.size() - 1 - text.find_last_not_of(" \t"));
  if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
  return text;
}

template <class T>
std::optional<T> numberOf(std::string_view text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

std::optional<double> finiteNumberIn(std::string_view text) {
  text = trimmed(text);
  const std::optional<double> value = numberOf<double>(text);
  if (!value || !std::isfinite(*value)) return std::nullopt;
  return value;
}

std::optional<int> wholeNumberIn(std::string_view text) { return numberOf<int>(trimmed(text)); }

double parseFiniteNumber(std::string_view text) {
  if (const auto value = finiteNumberIn(text)) return *value;
  throw Error(Error::Kind::InvalidArgument, "expected a finite number, got '" + printable(text, 40) + "'");
}

int parseWholeNumber(std::string_view text) {
  if (const auto value = wholeNumberIn(text)) return *value;
  throw Error(Error::Kind::InvalidArgument, "expected a whole number, got '" + printable(text, 40) + "'");
}

}  // namespace brdfbake
