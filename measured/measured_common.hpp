#pragma once
// Helpers shared by the measured-table readers (private to brdfbake_importers).
#include <brdfbake/core/error.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake::measured {

/// Error(InvalidInput) "<file>:<line>: <message>" (line 0: no line).
Error malformed(const std::string& file, int line, const std::string& message);

/// Largest text table read (ASTM, pbrt-v2): 256 MiB, far above the Cornell tables' 0.5 MB.
inline constexpr std::uintmax_t kMaxTableBytes = std::uintmax_t{256} << 20;

/// The whole file; Error(Io) if it cannot be read, Error(Resource) beyond kMaxTableBytes or when
/// its lines would not fit the memory budget.
std::string readFileBytes(const std::filesystem::path& path);
/// Up to `maxBytes` from the start of the file; Error(Io) if it cannot be read.
std::string readFilePrefix(const std::filesystem::path& path, std::size_t maxBytes);

/// One line of a text file, 1-based, without its "\n" or "\r\n".
struct TextLine {
  int number;
  std::string_view text;
};
std::vector<TextLine> splitLines(std::string_view content);
/// True if the content does not end with a line break (a cut-off last line).
bool lacksFinalNewline(std::string_view content);

std::string_view trim(std::string_view text);
/// Splits on `separator` (fields are trimmed).
std::vector<std::string_view> splitOn(std::string_view text, char separator);
/// Splits on runs of spaces and tabs.
std::vector<std::string_view> splitWhitespace(std::string_view text);

/// The whole field as a double (a leading '+' is accepted); std::nullopt if it is not a number.
/// "nan" and "inf" parse (as non-finite values): callers reject them with their own message.
std::optional<double> parseNumber(std::string_view field);
/// The whole field as a non-negative integer; std::nullopt otherwise.
std::optional<long long> parseCount(std::string_view field);
/// A finite number, or malformed(file, line, "<what> '<field>' is not a number" / "... is not finite").
double finiteField(std::string_view field, const std::string& file, int line, const std::string& what);

/// Shortest decimal text that reads back to the same double.
std::string formatShortest(double value);
/// "550nm" for 550; parses "550nm" / "550 nm" back (std::nullopt if the name is not a wavelength).
std::string wavelengthChannelName(double wavelengthNm);
std::optional<double> wavelengthFromChannelName(std::string_view name);

/// Checks theta in [0, pi/2] and finite phi (radians) for one sample; `line` may be 0.
void checkAngles(const SampleAngles& a, const std::string& file, int line, const std::string& where = {});

/// Adds the note about negative values (if any) that every reader adds.
void noteNegativeValues(MeasuredTable& table);

}  // namespace brdfbake::measured
