#pragma once
/// @file
/// Parsing JSON text from outside the program (specs, fit.json, map metadata) with limits that
/// keep hostile input from crashing us: nesting depth is bounded, and numbers that do not fit a
/// double are errors naming their JSON path, not exceptions from deep inside the parser.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace brdfbake {

/// Deepest nesting of arrays and objects accepted in any JSON input. Specs nest 5 levels deep;
/// anything far deeper is malformed or hostile (and would exhaust the stack of recursive code).
inline constexpr int kMaxJsonDepth = 64;

/// Largest JSON input accepted, in bytes (16 MiB). A spec, fit.json or map metadata takes a few KB;
/// the parsed document takes about 16 bytes per number, so this bounds a hostile array of zeros
/// to a few hundred MB.
inline constexpr std::size_t kMaxJsonBytes = std::size_t{16} << 20;

/// Parses `text` in time linear in its length. Throws Error(InvalidInput) with a message starting
/// "<source>:<line>:<column>: " for syntax errors; "<source>: <json path>: " for nesting deeper than
/// kMaxJsonDepth, numbers out of the double range (1e400) and keys or strings holding a NUL
/// character (\u0000, which would cut a file name short); "<source>: " for text over
/// kMaxJsonBytes. `source` and the keys in paths go through printable().
nlohmann::json parseJsonText(std::string_view text, const std::string& source);

/// Reads and parses a whole file with parseJsonText. Throws Error(Io) naming the file if it cannot
/// be read (including when it is a folder or not a regular file), Error(InvalidInput) before reading
/// a file over kMaxJsonBytes.
nlohmann::json readJsonFile(const std::filesystem::path& path);

}  // namespace brdfbake
