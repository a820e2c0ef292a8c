#pragma once
/// @file
/// Irradiance as spherical-harmonic coefficients: 3 bands (l = 0, 1, 2), 9 RGB coefficients, as
/// Filament's cmgen writes them, in a JSON file a renderer reads (docs/prefilter.md).
///
/// Convention (stated in the file too): the value is the radiance-equivalent irradiance
///   E(n) / pi = Σ_i c_i Y_i(n),   i = l (l + 1) + m,
/// so a Lambertian surface of albedo k_d reflects k_d Σ c_i Y_i(n), and a constant environment of
/// radiance L gives L. The coefficients already include the cosine-lobe convolution (Funk-Hecke:
/// A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4; Ramamoorthi & Hanrahan 2001, Eq. 8) and the 1/pi.
/// Y_i are the real orthonormal harmonics of sh.hpp (∫ Y_i Y_j dω = delta_ij, Condon-Shortley
/// phase included), evaluated at the unit normal (x, y, z) in the environment's frame (y up),
/// with the pole on +z:
///   Y_00 = 0.282095;  Y_1-1 = -0.488603 y;  Y_10 = 0.488603 z;  Y_11 = -0.488603 x;
///   Y_2-2 = 1.092548 x y;  Y_2-1 = -1.092548 y z;  Y_20 = 0.315392 (3 z^2 - 1);
///   Y_21 = -1.092548 x z;  Y_22 = 0.546274 (x^2 - y^2).
/// (cmgen folds the basis constants and signs into its coefficients; here they stay in Y_i.)

#include <brdfbake/env/environment.hpp>
#include <brdfbake/maps/sh.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>

namespace brdfbake {

/// The cosine lobe's Funk-Hecke coefficients A_l / pi for l = 0, 1, 2: 1, 2/3, 1/4.
std::vector<double> irradianceShScale();

/// Projects the environment's radiance onto the 9 harmonics (each texel's value times Y_i at its
/// centre times its exact solid angle, texelSolidAngle; unused cells skipped), then scales band l
/// by A_l / pi (see @file). The result evaluates to E(n) / pi.
ShExpansion irradianceSh(const Environment& environment);

/// The JSON document: {"format": "brdfbake-sh-irradiance", "version": 1, "bands": 3,
/// "convention": ..., "basis": [...], "frame": ..., "coefficients": [[r, g, b] x 9],
/// "environment": source}.
nlohmann::json irradianceShToJson(const ShExpansion& sh, const nlohmann::json& source);

/// Reads irradianceShToJson's document back. Throws Error(InvalidInput) naming `label` and the
/// JSON path of what is missing or wrong.
ShExpansion irradianceShFromJson(const nlohmann::json& document, const std::string& label);

/// The coefficients as Filament's cmgen prints them with --sh-shader (cmgen.cpp outputSh,
/// CubemapSH::computeIrradianceSH3Bands): 9 lines "(r, g, b); // Llm, irradiance, pre-scaled base",
/// l = 0..2, m = -l..l, each number fixed with 15 decimals in 18 columns. cmgen's coefficient i is
/// c_i k_i, k_i the constant and sign of Y_i above, so that E(n)/pi = sh[0] + sh[1] y + sh[2] z +
/// sh[3] x + sh[4] y x + sh[5] y z + sh[6] (3 z^2 - 1) + sh[7] z x + sh[8] (x^2 - y^2), which is the
/// sum Filament's shader (Irradiance_SphericalHarmonics) evaluates. (x, y, z) is the normal in the
/// environment's frame; cmgen's own run on a lat-long image works in the frame (x, y, -z), where
/// sh[2], sh[5] and sh[7] change sign.
std::string irradianceShCmgenText(const ShExpansion& sh);

/// How SH coefficients are written: "brdfbake", the JSON of irradianceShToJson (.json), or "cmgen",
/// the 9 RGB lines of irradianceShCmgenText (.txt).
enum class ShFormat { Brdfbake, Cmgen };
std::string_view toString(ShFormat format);
/// "brdfbake" | "cmgen"; throws Error(InvalidArgument) listing them.
ShFormat parseShFormat(std::string_view name);

/// Where SH coefficients go: a JSON file or, with `cmgen`, cmgen's lines.
struct ShOutput {
  std::filesystem::path file;
  bool cmgen = false;

  /// What is wrong with the file's extension for its format ("" when nothing).
  std::string problem() const;
};

/// The constants k_i of the basis above (Y_i = k_i b_i, b_i the polynomials of cmgen's lines).
std::vector<double> irradianceShBasisConstants();

/// True if `document` says it is an SH irradiance file ("format").
bool isIrradianceShDocument(const nlohmann::json& document);

/// Writes the JSON atomically (writeFileAtomically). Throws Error(InvalidArgument) if `path` is an
/// input in `inputs`.
void writeIrradianceSh(const ShExpansion& sh, const nlohmann::json& source, const std::filesystem::path& path,
                       const std::vector<std::filesystem::path>& inputs = {});

}  // namespace brdfbake
