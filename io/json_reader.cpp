#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/json_reader.hpp>

#include <sstream>

namespace brdfbake {

Error specError(const std::string& path, const std::string& message) {
  // Messages quote values of the input: made printable whole, as a last guard (each quoted value is
  // shortened where it is quoted).
  return Error(Error::Kind::InvalidInput, path + ": " + printableMessage(message, 2000));
}

std::string describe(const nlohmann::json& value) {
  // Containers are summarised, never dumped whole: a hostile value may be huge.
  if (value.is_array() && !value.empty() && (value.size() > 8 || !value[0].is_primitive())) {
    return "an array of " + std::to_string(value.size()) + " values";
  }
  if (value.is_object() && !value.empty()) return "an object with " + std::to_string(value.size()) + " keys";
  return printable(value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), 60);
}

namespace {
std::string formatNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
}  // namespace

JsonObjectReader::JsonObjectReader(const nlohmann::json& value, std::string path)
    : object_(value), path_(std::move(path)) {
  if (!object_.is_object())
    throw specError(path_.empty() ? "(root)" : path_, "must be an object, got " + describe(value));
}

std::string JsonObjectReader::child(const std::string& key) const {
  const std::string shown = printable(key, 60);
  return path_.empty() ? shown : path_ + "." + shown;
}

const nlohmann::json* JsonObjectReader::find(const std::string& key) {
  known_.insert(key);
  const auto it = object_.find(key);
  if (it == object_.end()) return nullptr;
  read_.insert(key);
  return &*it;
}

const nlohmann::json& JsonObjectReader::require(const std::string& key) {
  const auto* value = find(key);
  if (!value) throw specError(child(key), "required");
  return *value;
}

std::string JsonObjectReader::string(const std::string& key) {
  const auto& value = require(key);
  if (!value.is_string()) throw specError(child(key), "must be a string, got " + describe(value));
  return value.get<std::string>();
}

std::optional<std::string> JsonObjectReader::optionalString(const std::string& key) {
  if (!has(key)) return std::nullopt;
  return string(key);
}

double JsonObjectReader::asNumber(const nlohmann::json& value, const std::string& path) {
  if (!value.is_number()) throw specError(path, "must be a number, got " + describe(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw specError(path, "must be finite");
  return v;
}

double JsonObjectReader::number(const std::string& key, double minimum, double maximum, bool exclusiveMinimum) {
  const double v = asNumber(require(key), child(key));
  const bool low = exclusiveMinimum ? !(v > minimum) : !(v >= minimum);
  if (low)
    throw specError(child(key), std::string("must be ") + (exclusiveMinimum ? "> " : ">= ") + formatNumber(minimum) +
                                    ", got " + formatNumber(v));
  if (v > maximum) throw specError(child(key), "must be <= " + formatNumber(maximum) + ", got " + formatNumber(v));
  return v;
}

double JsonObjectReader::number(const std::string& key, double fallback, double minimum, double maximum,
                                bool exclusiveMinimum) {
  return has(key) ? number(key, minimum, maximum, exclusiveMinimum) : fallback;
}

int JsonObjectReader::integer(const std::string& key, int minimum, int maximum) {
  const auto& value = require(key);
  if (!value.is_number_integer()) throw specError(child(key), "must be an integer, got " + describe(value));
  // Unsigned values beyond long long (18446744073709551615) are out of range, never wrapped to -1.
  bool inRange = false;
  if (value.is_number_unsigned()) {
    const unsigned long long u = value.get<unsigned long long>();
    inRange = maximum >= 0 && u <= static_cast<unsigned long long>(maximum) && static_cast<long long>(u) >= minimum;
  } else {
    const long long v = value.get<long long>();
    inRange = v >= minimum && v <= maximum;
  }
  if (!inRange) {
    throw specError(child(key), "must be in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "], got " +
                                    value.dump());
  }
  return value.get<int>();
}

int JsonObjectReader::integer(const std::string& key, int fallback, int minimum, int maximum) {
  return has(key) ? integer(key, minimum, maximum) : fallback;
}

bool JsonObjectReader::boolean(const std::string& key) {
  const nlohmann::json& value = require(key);
  if (!value.is_boolean()) throw specError(child(key), "must be true or false, got " + describe(value));
  return value.get<bool>();
}

bool JsonObjectReader::boolean(const std::string& key, bool fallback) { return has(key) ? boolean(key) : fallback; }

Rgb JsonObjectReader::asColor(const nlohmann::json& value, const std::string& path) {
  Rgb c;
  if (value.is_number()) {
    c.setConstant(asNumber(value, path));
  } else if (value.is_array() && value.size() == 3) {
    for (int i = 0; i < 3; ++i) c[i] = asNumber(value[i], path + "[" + std::to_string(i) + "]");
  } else {
    throw specError(path, "must be [r, g, b] or one number, got " + describe(value));
  }
  for (int i = 0; i < 3; ++i) {
    if (c[i] < 0) throw specError(path, "must be >= 0, got " + describe(value));
    if (c[i] > kMaxColor) {
      throw specError(
          path, "must be <= " + formatNumber(kMaxColor) + " per channel (docs/limits.md), got " + describe(value));
    }
  }
  return c;
}

Rgb JsonObjectReader::color(const std::string& key) { return asColor(require(key), child(key)); }
Rgb JsonObjectReader::color(const std::string& key, const Rgb& fallback) { return has(key) ? color(key) : fallback; }

Vec3 JsonObjectReader::asDirection(const nlohmann::json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3) throw specError(path, "must be [x, y, z], got " + describe(value));
  Vec3 d;
  for (int i = 0; i < 3; ++i) d[i] = asNumber(value[i], path + "[" + std::to_string(i) + "]");
  // Scaled by the largest component first, so [1e300, 1e300, 1e300] normalises without overflow.
  const double largest = d.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) throw specError(path, "must be a non-zero vector, got " + describe(value));
  return (d / largest).normalized();
}

Vec3 JsonObjectReader::direction(const std::string& key) { return asDirection(require(key), child(key)); }

JsonObjectReader JsonObjectReader::object(const std::string& key) { return JsonObjectReader(require(key), child(key)); }

const nlohmann::json& JsonObjectReader::array(const std::string& key, std::size_t maxEntries) {
  const auto& value = require(key);
  if (!value.is_array()) throw specError(child(key), "must be an array, got " + describe(value));
  if (value.size() > maxEntries) {
    throw specError(child(key), "at most " + std::to_string(maxEntries) + " entries (docs/limits.md), got " +
                                    std::to_string(value.size()));
  }
  return value;
}

void JsonObjectReader::finish() const {
  for (const auto& [key, value] : object_.items()) {
    if (read_.count(key)) continue;
    std::string known;
    for (const auto& k : known_) known += (known.empty() ? "" : ", ") + k;
    const auto meant = closestName(key, std::vector<std::string>(known_.begin(), known_.end()));
    throw specError(child(key), "unknown key" + (meant ? ", did you mean '" + *meant + "'?" : std::string()) +
                                    (known.empty() ? std::string() : " (known keys: " + known + ")"));
  }
}

}  // namespace brdfbake
