#pragma once
/// @file
/// Running gnuplot (an optional external program) for charts: `brdfbake fit --report` and the
/// benches. gnuplot is found on PATH, or taken from the environment variable BRDFBAKE_GNUPLOT when
/// it is set (an empty value means "no gnuplot", which the tests use).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// The gnuplot executable, or std::nullopt when there is none.
std::optional<std::filesystem::path> findGnuplot();

/// Runs gnuplot on `script`, written to a scratch file (removed afterwards, and on an interrupt). Throws
/// Error(InvalidArgument) "gnuplot not found ..." when there is none, Error(Io) with gnuplot's own messages when it
/// fails.
void runGnuplot(const std::string& script);

/// `text` quoted for a gnuplot string literal (single quotes, quotes doubled).
std::string gnuplotQuote(const std::string& text);

/// Throws Error(InvalidArgument) unless `output` ends in .png or .svg (checked before the work).
void checkChartPath(const std::filesystem::path& output);

/// Draws gnuplot script bodies (everything after "set terminal ... / set output ...") into `output`
/// (.png or .svg), atomically: one body draws a 900 x 600 chart; several draw one panel each,
/// stacked in one picture 600 pixels taller per panel. Throws Error(InvalidArgument) for another
/// extension and Error(Io) naming `output` when gnuplot is missing or fails.
void renderChart(const std::vector<std::string>& panels, const std::filesystem::path& output);

}  // namespace brdfbake
