#pragma once
/// @file
/// Parsing JSON text from outside the program (specs, fit.json, map metadata) with limits that
/// keep hostile input from crashing us: nesting depth is bounded, and numbers that do not fit a
/// double are errors naming their JSON path, not exceptions from deep inside the parser.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace brdfbake {

/// Deepest nesting of arrays and objects accepted in any JSON input. Specs nest 5 levels deep;
/// anything far deeper is malformed or hostile (and would exhaust the stack of recursive code).
inline constexpr int kMaxJsonDepth = 64;

/// Parses `text`. Throws Error(InvalidInput) with a message starting "<source>:<line>:<column>: "
/// for syntax errors, "<source>: <json path>: " for nesting deeper than kMaxJsonDepth and for
/// numbers out of the double range (1e400).
nlohmann::json parseJsonText(std::string_view text, const std::string& source);

/// Reads and parses a whole file with parseJsonText. Throws Error(Io) naming the file if it cannot
/// be read (including when it is a folder).
nlohmann::json readJsonFile(const std::filesystem::path& path);

}  // namespace brdfbake
