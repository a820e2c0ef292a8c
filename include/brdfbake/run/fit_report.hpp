#pragma once
/// @file
/// `brdfbake fit --report`: a PNG chart of measured against fitted values in the plane of
/// incidence, one panel per incident angle, drawn by gnuplot (core/gnuplot.hpp).
///
/// Each panel plots the BRDF (1/sr, log scale) against the signed outgoing angle theta_s in
/// degrees: positive on the mirror side (phi_s = 180 degrees), negative on the retro side
/// (phi_s = 0); measured samples of the plane as points, the model as lines, the mirror direction
/// dashed. Up to three channels: R, G, B, or for spectral tables the wavelengths nearest 650, 550
/// and 450 nm, drawn in red, green and blue; other tables their first three channels. Measured
/// values <= 0 cannot be drawn on a log scale and are left out.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <filesystem>
#include <string>

namespace brdfbake {

/// The gnuplot script that draws the chart into `png` (exposed for tests).
std::string fitReportScript(const std::filesystem::path& png, const MeasuredTable& table, const LobeModel& model,
                            const std::string& title);

/// Draws the chart into `png` atomically (renderGnuplotOutput). Throws Error(InvalidArgument) when
/// the table and model channel counts differ or gnuplot is missing, Error(Io) naming `png` when
/// gnuplot fails or the picture is incomplete.
void writeFitReport(const std::filesystem::path& png, const MeasuredTable& table, const LobeModel& model,
                    const std::string& title = {});

}  // namespace brdfbake
