#pragma once
// Charts through gnuplot (Debian's gnuplot-nox): brdfbake writes the script, gnuplot draws.
#include <filesystem>
#include <string>

namespace brdfbake::cli {

/// Runs a gnuplot script body (everything after "set terminal ... / set output ...") to draw
/// `output` (.png or .svg, 900 x 600), atomically: into a temporary file renamed into place.
/// Throws Error(InvalidArgument) for another extension and Error(Io) when gnuplot is missing or
/// fails.
void renderWithGnuplot(const std::string& body, const std::filesystem::path& output);

/// Throws Error(InvalidArgument) unless `output` ends in .png or .svg (checked before the work).
void checkChartPath(const std::filesystem::path& output);

}  // namespace brdfbake::cli
