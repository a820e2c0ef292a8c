#pragma once
/// @file
/// The sample geometry of the Cornell gonioreflectometer tables, and tables made on it: synthetic
/// tables from known lobes (tests, data_samples/) and MERL tables resampled for fitting.
///
/// The geometry, checked sample for sample against Cornell's published tables (tests/fit):
/// - theta_i = 10, 20, ..., 80 degrees, phi_i = 0;
/// - outgoing directions on 10 equal-area rings sqrt(2) sin(theta_s / 2) = k / 10, k = 0..9; ring
///   k > 0 has the 4k + 1 azimuths phi_s = -180 + j 45 / k degrees, j = 1..4k (j = 4k is 0, the
///   retro side), plus +180 (the mirror side, written as +180 rather than -180); ring 0 is the
///   normal (phi_s = 0). 190 directions per incident angle, one half of the hemisphere.
/// - holes: the detector shadows the source, so every direction within 17 degrees of wi is
///   missing (the files' nearest present sample is 17.04 degrees away, the farthest missing one
///   16.74), and at theta_i = 80 degrees the sample theta_s = 79.05, phi_s = -175 degrees is
///   missing too. 1439 samples in all, as in every Cornell file.
/// - angles are rounded to 6 decimals, as the files store them.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace brdfbake {

/// The Cornell sample directions (see @file), ordered by theta_i, ring, azimuth. `holes` false
/// gives the full 8 x 190 grid.
std::vector<SampleAngles> cornellSampleAngles(bool holes = true);

/// True for the directions the Cornell tables lack (see @file); angles in radians.
bool isCornellHole(const SampleAngles& angles);

/// A table on the Cornell geometry whose values are `model`'s BRDF times (1 + noise g), g a
/// standard normal deviate drawn from std::mt19937(seed) (relative noise; `noise` = 0.01 is 1 %).
/// Channels, kind and wavelengths follow the model (spectral when it has wavelengths; R, G, B
/// trichromatic; else monochrome); the header names the generator and its parameters.
/// Throws Error(InvalidArgument) for a model that does not validate or noise outside [0, 1).
MeasuredTable makeSyntheticTable(const LobeModel& model, double noise = 0.01, std::uint32_t seed = 1,
                                 bool holes = true);

/// A MERL table sampled on the full Cornell grid (no holes) so that the fitter sees it as it sees
/// the Cornell tables: one sample per grid direction whose MERL bin was measured (MerlTable::
/// evaluate, nearest bin), channels R, G, B. The table's notes say how many bins were unmeasured.
MeasuredTable sampleMerlOnCornellGrid(const MerlTable& merl);

/// Reads any measured table for fitting: readMeasuredTable for ASTM, pbrt and MAT files, and for
/// MERL files (given or detected) readMerl then sampleMerlOnCornellGrid.
MeasuredTable readTableForFitting(const std::filesystem::path& path, TableFormat format = TableFormat::Auto);

}  // namespace brdfbake
