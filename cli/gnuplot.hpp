#pragma once
// Charts through gnuplot (Debian's gnuplot-nox): brdfbake writes the script, gnuplot draws.
#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake::cli {

/// Runs gnuplot script bodies (everything after "set terminal ... / set output ...") to draw
/// `output` (.png or .svg), atomically: into a temporary file renamed into place. One body draws a
/// 900 x 600 chart; several draw one panel each, stacked in one picture 600 pixels taller per
/// panel. Throws Error(InvalidArgument) for another extension and Error(Io) when gnuplot is missing
/// or fails.
void renderWithGnuplot(const std::string& body, const std::filesystem::path& output);
void renderWithGnuplot(const std::vector<std::string>& panels, const std::filesystem::path& output);

/// Throws Error(InvalidArgument) unless `output` ends in .png or .svg (checked before the work).
void checkChartPath(const std::filesystem::path& output);

}  // namespace brdfbake::cli
