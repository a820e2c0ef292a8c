#pragma once
/// @file
/// Reading JSON objects with errors that name the JSON path, and rejecting keys nobody read.

#include <brdfbake/core/color.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/io/json_text.hpp>  // readJsonFile, parseJsonText

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace brdfbake {

/// Largest colour component a JSON input may give (an irradiance, albedo or map colour): far above
/// any real light (the sun gives about 1e5 lux), far below where sums of lights and lobes overflow
/// the float samples of a map (3.4e38).
inline constexpr double kMaxColor = 1e6;

/// Most entries of a JSON array read with JsonObjectReader::array unless the caller gives its own
/// limit (docs/limits.md).
inline constexpr std::size_t kMaxJsonArrayEntries = 4096;

/// Error(InvalidInput) with message "<path>: <message>".
Error specError(const std::string& path, const std::string& message);

/// A view of one JSON object at a known path ("maps[0].material"). Every accessor marks its key
/// as read; finish() throws for keys nobody read, so typos never pass silently.
class JsonObjectReader {
 public:
  /// Throws specError(path, "must be an object") if `value` is not an object.
  JsonObjectReader(const nlohmann::json& value, std::string path);

  const std::string& path() const { return path_; }
  /// The path of a child key: "<path>.<key>" (or "<key>" at the root).
  std::string child(const std::string& key) const;
  bool has(const std::string& key) const {
    known_.insert(key);
    return object_.contains(key);
  }
  /// The raw value, marked read; nullptr if absent.
  const nlohmann::json* find(const std::string& key);
  /// The raw value, marked read; throws "<path>.<key>: required" if absent.
  const nlohmann::json& require(const std::string& key);

  std::string string(const std::string& key);
  std::optional<std::string> optionalString(const std::string& key);
  /// A finite number; `minimum`/`maximum` bounds with `exclusiveMinimum` for "> min".
  double number(const std::string& key, double minimum = -HUGE_VAL, double maximum = HUGE_VAL,
                bool exclusiveMinimum = false);
  double number(const std::string& key, double fallback, double minimum, double maximum, bool exclusiveMinimum);
  int integer(const std::string& key, int minimum, int maximum);
  int integer(const std::string& key, int fallback, int minimum, int maximum);
  /// true or false (no other type is taken for one).
  bool boolean(const std::string& key);
  bool boolean(const std::string& key, bool fallback);
  /// [r, g, b] of numbers in [0, kMaxColor], or one number for grey.
  Rgb color(const std::string& key);
  Rgb color(const std::string& key, const Rgb& fallback);
  /// [x, y, z], finite and non-zero; returned normalized.
  Vec3 direction(const std::string& key);
  /// An object member, for nested reading.
  JsonObjectReader object(const std::string& key);
  /// An array member of at most `maxEntries` entries; throws unless it is one ("<path>: at most N
  /// entries (docs/limits.md), got M").
  const nlohmann::json& array(const std::string& key, std::size_t maxEntries = kMaxJsonArrayEntries);

  /// The string at `key` (or `fallback` when absent and a fallback is given) turned into a value
  /// by `parse`, a parse* function that throws Error naming the accepted names; its error is
  /// rethrown as a specError at the key's JSON path.
  template <class Parse>
  auto parsed(const std::string& key, Parse&& parse, std::optional<std::string> fallback = std::nullopt) {
    const std::string text = fallback && !has(key) ? *fallback : string(key);
    try {
      return parse(text);
    } catch (const Error& e) {
      throw specError(child(key), e.what());
    }
  }

  /// Throws for the first key that was never read, listing the keys this object accepts.
  void finish() const;

  /// Helpers for values that are not members of this object.
  static double asNumber(const nlohmann::json& value, const std::string& path);
  static Rgb asColor(const nlohmann::json& value, const std::string& path);
  static Vec3 asDirection(const nlohmann::json& value, const std::string& path);

 private:
  const nlohmann::json& object_;
  std::string path_;
  std::set<std::string> read_;
  mutable std::set<std::string> known_;  // every key asked for, present or not
};

/// "[1, 2, 3]" style rendering of a JSON value for messages (truncated).
std::string describe(const nlohmann::json& value);

}  // namespace brdfbake
