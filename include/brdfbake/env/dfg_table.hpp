#pragma once
/// @file
/// The split-sum DFG lookup table for GGX (Karis 2013; Filament's cmgen --ibl-dfg): the two numbers of
/// brdf/split_sum.hpp over n.v and the perceptual roughness, as an image an engine samples.
///
/// Layout (docs/engines.md): a W x H image, texel (i, j) at n.v = (i + 0.5) / W along x and the
/// perceptual roughness R = (j + 0.5) / H along y (alpha = R^2), row j = 0 first (the top row of an
/// OpenEXR or PNG, the first row in memory of a KTX2/DDS texture), so a renderer samples
/// texture(dfg, vec2(n.v, R)) with the rows uploaded in file order (OpenGL t = 0 is the first row).
/// Channels: R = DFG1, G = DFG2, B = 0, A = 1; single scattering E = f0 DFG1 + f90 DFG2,
/// multiple-scattering form E = mix(DFG1, DFG2, f0) (split_sum.hpp).
///
/// Accuracy: each texel is a product Gauss-Legendre quadrature over the half vector h: theta_h through
/// the GGX distribution's inverse CDF, split where the azimuth range that keeps the light above the
/// horizon changes form (theta_h = pi/4 -+ theta_v/2, found in closed form) with nodes gathered at
/// each band's ends, and the azimuth over that range. With the defaults it agrees with a brute-force
/// sum over the light direction to 1e-3 (absolute) at every texel of roughness >= 0.1, far better away
/// from grazing (tests/env/test_dfg_table.cpp); more points and panels converge to 1e-8.

#include <brdfbake/core/context.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/image.hpp>

#include <filesystem>
#include <string_view>

namespace brdfbake {

enum class DfgForm { SingleScattering, MultipleScattering };

/// "single", "multiscatter".
std::string_view toString(DfgForm form);
/// Inverse of toString; throws Error(InvalidArgument) naming the accepted values.
DfgForm parseDfgForm(std::string_view name);

struct DfgOptions {
  int width = 128, height = 128;  ///< texels along n.v and roughness, each in [1, 4096]
  DfgForm form = DfgForm::SingleScattering;
  /// Gauss-Legendre points per panel and panels, in theta_h (inverse CDF) and in azimuth.
  int points = 12, panels = 4;
  /// Throws Error(InvalidArgument) naming the value out of range.
  void validate() const;
};

/// DFG1 and DFG2 (split_sum.hpp) at n.v in (0, 1] and perceptual roughness in [0, 1].
struct DfgTerms {
  double first = 0.0, second = 0.0;
};
DfgTerms dfgTerms(double cosView, double roughness, DfgForm form, int points = 12, int panels = 4);

/// The table (see @file): a float RGBA image with metadata {"dfg_table": {form, width, height, axes,
/// channels, formula, roughness}}.
Image dfgTable(const DfgOptions& options = {}, const Context& context = {});

/// Writes the table with writeImage as float texels (.exr, .tif, .ktx2, .ktx, .dds). Throws
/// Error(InvalidArgument) naming the file for .png and .hdr (8-bit sRGB, a shared exponent), and what
/// writeImage throws.
WriteReport writeDfgTable(const Image& table, const std::filesystem::path& path, const WriteOptions& options = {});

}  // namespace brdfbake
