#pragma once
/// @file
/// A BRDF read from a file, whatever the file holds: a fit.json (the fitted lobes), a measured
/// table (.astm, .brdf, .mat: interpolated, fit/table_interpolation.hpp; MERL .binary: the nearest
/// bin) or a JSON file holding one material object ({"model": "phong", ...}: the BRDF it implies,
/// shade / (n.l)). `brdfbake eval` evaluates it; the Python module's fit results too.

#include <brdfbake/core/math.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace brdfbake {

struct BrdfFile {
  std::string kind;                   ///< "fit", "table", "merl" or "material"
  std::vector<std::string> channels;  ///< channel names ("R", "G", "B", or wavelengths as fitted)
  /// BRDF per channel (1/sr) for light `wi` and view `wo` in the local frame (z the normal), both
  /// pointing away from the surface; 0 where either is at or below the horizon. Thread-safe.
  std::function<Eigen::VectorXd(const Vec3& wi, const Vec3& wo)> evaluate;
};

/// Reads the BRDF in `file` (see @file); tables of `format` (Auto: by content). Throws Error(Io)
/// for an unreadable file, Error(InvalidInput) naming the file for one that is none of these (a
/// bake spec included), Error(InvalidArgument) for a material that has no BRDF (a reflectance map).
BrdfFile loadBrdf(const std::filesystem::path& file, TableFormat format = TableFormat::Auto);

}  // namespace brdfbake
