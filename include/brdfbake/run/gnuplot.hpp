#pragma once
/// @file
/// Charts through gnuplot (an optional external program; Debian's gnuplot-nox), the one way every
/// part draws one (`fit --report`, `chart`, `interpolation`, the benches). gnuplot is found on PATH,
/// or taken from the environment variable BRDFBAKE_GNUPLOT when it is set (empty: no gnuplot, which
/// the tests use). It runs as a child process (posix_spawn) that the interrupt cleanup
/// (removeTemporaryFilesNow) stops, and draws into the temporary of an AtomicOutput, so a chart
/// appears whole or not at all.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// The gnuplot executable, or std::nullopt when there is none (then gnuplotMissingReason() says why).
std::optional<std::filesystem::path> findGnuplot();

/// Why findGnuplot() finds none: "BRDFBAKE_GNUPLOT=/x: no such file", "BRDFBAKE_GNUPLOT=/x: not an
/// executable file", "BRDFBAKE_GNUPLOT is empty (charts are off)" or "gnuplot not found on PATH
/// (Debian: apt-get install gnuplot-nox)".
std::string gnuplotMissingReason();

/// Runs gnuplot on `script` (written to a scratch file, removed afterwards and on an interrupt),
/// stdin and stdout /dev/null, stderr kept. Throws Error(InvalidArgument) "<reason>; charts need
/// gnuplot" when there is none, Error(Io) "gnuplot exited with status 1: <its messages>" or
/// "gnuplot was killed by signal 9 (Killed)" when it fails (its messages through printable()).
void runGnuplot(const std::string& script);

/// Runs the script `script(temporary)`, which must draw into the file it is given, and commits that
/// file as `output` (AtomicOutput): checked to be non-empty and complete (a PNG ends with its IEND
/// chunk, an SVG with "</svg>") before it replaces anything. Errors as runGnuplot, prefixed with
/// the output's name; Error(Io) "<output>: gnuplot wrote an incomplete PNG (N bytes)".
void renderGnuplotOutput(const std::filesystem::path& output,
                         const std::function<std::string(const std::filesystem::path& temporary)>& script);

/// Throws Error(InvalidArgument) unless `output` ends in .png or .svg (check it before the work).
void checkChartPath(const std::filesystem::path& output);

/// Draws gnuplot script bodies (everything after "set terminal ... / set output ...") into `output`
/// (.png through pngcairo or .svg), through renderGnuplotOutput. One body draws a 900 x 600 chart;
/// several draw one panel each, stacked in one picture 600 pixels taller per panel.
void renderChart(const std::vector<std::string>& panels, const std::filesystem::path& output);
void renderChart(const std::string& body, const std::filesystem::path& output);

/// `text` quoted for a gnuplot string literal (single quotes, quotes doubled, newlines dropped).
std::string gnuplotQuote(const std::string& text);

}  // namespace brdfbake
