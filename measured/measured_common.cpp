#include "measured_common.hpp"
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/io/files.hpp>

#include <brdfbake/core/math.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace brdfbake::measured {

Error malformed(const std::string& file, int line, const std::string& message) {
  // Messages quote fields of the file: made printable whole, as a last guard (each quoted field is
  // shortened where it is quoted).
  return Error::atFile(Error::Kind::InvalidInput, file, line, printableMessage(message, 2000));
}

namespace {
std::ifstream openForReading(const std::filesystem::path& path) {
  requireInputFile(path, "measured table");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error::atFile(Error::Kind::Io, path.string(), 0, std::string("cannot open: ") + std::strerror(errno));
  return in;
}
}  // namespace

std::string readFileBytes(const std::filesystem::path& path) {
  std::string content = readTextFile(path, "measured table", kMaxTableBytes);
  // Each line becomes a TextLine and, for data rows, a row of values: budget them before splitting.
  const auto lines = static_cast<double>(std::count(content.begin(), content.end(), '\n'));
  requireWithinMemoryBudget(64.0 * lines,
                            printable(path.string()) + ": " + std::to_string(static_cast<long long>(lines)) + " lines");
  return content;
}

std::string readFilePrefix(const std::filesystem::path& path, std::size_t maxBytes) {
  std::ifstream in = openForReading(path);
  std::string prefix(maxBytes, '\0');
  in.read(prefix.data(), static_cast<std::streamsize>(maxBytes));
  if (in.bad()) throw Error::atFile(Error::Kind::Io, path.string(), 0, "read error");
  prefix.resize(static_cast<std::size_t>(in.gcount()));
  return prefix;
}

std::vector<TextLine> splitLines(std::string_view content) {
  std::vector<TextLine> lines;
  int number = 0;
  std::size_t start = 0;
  while (start < content.size()) {
    std::size_t end = content.find('\n', start);
    if (end == std::string_view::npos) end = content.size();
    std::string_view text = content.substr(start, end - start);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    lines.push_back({++number, text});
    start = end + 1;
  }
  return lines;
}

bool lacksFinalNewline(std::string_view content) { return !content.empty() && content.back() != '\n'; }

std::string_view trim(std::string_view text) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; };
  while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && isSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> splitOn(std::string_view text, char separator) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    fields.push_back(trim(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return fields;
}

std::vector<std::string_view> splitWhitespace(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r') ++i;
    if (i > start) tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

std::optional<double> parseNumber(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size()) return std::nullopt;
  return value;
}

std::optional<long long> parseCount(std::string_view field) {
  long long value = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || ec != std::errc() || end != field.data() + field.size() || value < 0) return std::nullopt;
  return value;
}

double finiteField(std::string_view field, const std::string& file, int line, const std::string& what) {
  const std::optional<double> value = parseNumber(field);
  if (!value) throw malformed(file, line, what + " '" + printable(field, 60) + "' is not a number");
  if (!std::isfinite(*value)) throw malformed(file, line, what + " '" + printable(field, 60) + "' is not finite");
  return *value;
}

std::string formatShortest(double value) {
  char text[64];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  return std::string(text, ec == std::errc() ? end : text);
}

std::string wavelengthChannelName(double wavelengthNm) { return formatShortest(wavelengthNm) + "nm"; }

std::optional<double> wavelengthFromChannelName(std::string_view name) {
  name = trim(name);
  if (name.size() < 3) return std::nullopt;
  const std::string_view unit = name.substr(name.size() - 2);
  if (unit != "nm" && unit != "NM" && unit != "Nm") return std::nullopt;
  const std::optional<double> value = parseNumber(trim(name.substr(0, name.size() - 2)));
  if (!value || !std::isfinite(*value) || *value <= 0.0) return std::nullopt;
  return value;
}

void checkAngles(const SampleAngles& a, const std::string& file, int line, const std::string& where) {
  constexpr double kSlack = 1e-6;
  const auto checkTheta = [&](double theta, const char* name) {
    if (!(theta >= -kSlack && theta <= kPi / 2 + kSlack))
      throw malformed(file, line,
                      where + name + " = " + formatShortest(theta) +
                          " is outside [0, pi/2] (angles must be radians, from the normal)");
  };
  const auto checkPhi = [&](double phi, const char* name) {
    if (!(std::abs(phi) <= kTwoPi + kSlack))
      throw malformed(
          file, line,
          where + name + " = " + formatShortest(phi) + " is outside [-2 pi, 2 pi] (angles must be radians)");
  };
  checkTheta(a.thetaIn, "theta_i");
  checkPhi(a.phiIn, "phi_i");
  checkTheta(a.thetaOut, "theta_s");
  checkPhi(a.phiOut, "phi_s");
}

void noteNegativeValues(MeasuredTable& table) {
  const auto negatives = (table.values.array() < 0.0).count();
  if (negatives > 0)
    table.notes.push_back(std::to_string(negatives) + " of " + std::to_string(table.values.size()) +
                          " values are negative; they are kept as stored in the file");
}

}  // namespace brdfbake::measured
