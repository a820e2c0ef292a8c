#pragma once
/// @file
/// Every output of `brdfbake bake` and `brdfbake prefilter`, opened for lookups the way a renderer
/// makes them. `brdfbake sample`, `info`, `convert` and `preview` all read files through this.
///
/// | kind              | files                                                   | a renderer looks it up |
/// |-------------------|---------------------------------------------------------|---------------------------------------------------------|
/// | Map               | one map (sphere, paraboloid, cube cross, lat-long); a   | bilinear at the direction
/// (sampleBilinear)              | |                   | cube's six faces; one mip level (STEM_mipK.EXT or a     | | |
/// | level of a tiled MIP-mapped file)                       | | | RadialProfile     | N x 1, metadata
/// "parameterization": "profile"           | linear in u = |d - axis| / 2 (radial_profile.hpp)       | | ElevationStack
/// | STEM_elev0.EXT ... STEM_elev{K-1}.EXT (open STEM.EXT)   | each slice bilinear at d, then linear in the model's |
/// |                   |                                                         | elevation coordinate t(n.v)
/// (prefilter_stack.hpp)       | | FresnelTable    | N x 1, "parameterization": "fresnel_table"            | linear in
/// cos theta = n.v, texel i at (i + 0.5) / N     | | ShIrradiance      | JSON of spherical-harmonic coefficients
/// (sh_irradiance) | Σ_i c_i Y_i(n) at the normal                            |
///
/// The lookup direction is the one the map is indexed by, in the map's frame: the reflected
/// direction r for most maps, the normal n for irradiance (prefiltered irradiance maps other than
/// sphere maps, which hold E at r for their one view, and SH irradiance). n.v ("cos_view") is the
/// cosine between the surface normal and the direction towards the viewer.

#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/sh.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

enum class OutputKind { Map, RadialProfile, ElevationStack, FresnelTable, ShIrradiance };

/// "map", "radial_profile", "elevation_stack", "fresnel_table", "sh_irradiance".
std::string_view toString(OutputKind kind);

struct OpenOutputOptions {
  /// A plain image (no brdfbake metadata) is read as a map of this kind; without it, an error.
  std::optional<ParameterizationKind> from;
  /// How the caller names `from` in messages (the CLI: "--from"); the error for a plain image
  /// without `from` then says to pass it.
  std::string fromName = "the parameterization";
  /// Mip level (>= 0) of a map, a cube's faces or a stack's slices: readMap's `mipLevel`.
  int mipLevel = 0;
};

/// One output, read whole, with its lookup (see @file). Immutable and thread-safe after open().
class BakedOutput {
 public:
  /// Opens `path`: a file, STEM.EXT of a cube's six faces or of an elevation stack (which then
  /// need not exist), or an SH irradiance JSON. Throws Error(Io) for a missing file,
  /// Error(InvalidInput) for files that are none of the kinds (naming the file) and
  /// Error(InvalidArgument) for a mip level of a kind without levels.
  static BakedOutput open(const std::filesystem::path& path, const OpenOutputOptions& options = {});
  /// A map held in memory (a job's result), looked up as if it had been written and read back:
  /// `image` laid out by a map of `info`'s parameterization and resolution, its metadata `info`'s
  /// (irradiance maps say "irradiance_quantity" in info.spec["prefilter"]). No files.
  static BakedOutput fromMap(Image image, const MapInfo& info);

  OutputKind kind() const { return kind_; }
  /// Every file read.
  const std::vector<std::filesystem::path>& files() const { return files_; }
  /// The metadata (of slice 0 for a stack, of face +x for faces).
  const nlohmann::json& metadata() const { return metadata_; }

  /// False only for a Fresnel table, a function of n.v alone.
  bool usesDirection() const { return kind_ != OutputKind::FresnelTable; }
  /// True for an elevation stack and a Fresnel table.
  bool usesCosView() const { return kind_ == OutputKind::ElevationStack || kind_ == OutputKind::FresnelTable; }
  /// True if the lookup direction is the normal n, not the reflected direction r (see @file).
  bool indexedByNormal() const { return indexedByNormal_; }
  /// Sphere maps and profiles about the view live in eye space: the view is +z only.
  bool eyeSpace() const { return eyeSpace_; }

  /// The value at a lookup direction (finite, non-zero; ignored by a Fresnel table) and n.v
  /// (in [0, 1]; used by stacks and Fresnel tables only, which need it). Throws
  /// Error(InvalidArgument) if a needed parameter is missing or out of range. Alpha is the map's
  /// coverage (1 for profiles and SH).
  Rgba lookup(const Vec3& direction, std::optional<double> cosView = std::nullopt) const;

  /// What a renderer shows at a surface point of unit normal n seen from unit view v (towards the
  /// viewer), both in the map's frame: lookup at r = 2 (n.v) n - v, or at n (indexedByNormal),
  /// with n.v clamped to [0, 1].
  Rgba shade(const Vec3& normal, const Vec3& view) const;

  /// A 2-D map's image and parameterization (kind Map only; else null): fast paths such as
  /// per-vertex texture coordinates in renderPreview.
  const MapFile* map() const { return kind_ == OutputKind::Map ? &maps_.front() : nullptr; }

  /// For `brdfbake info`: kind, files, size, parameterization or axis, how to look it up, and the
  /// metadata.
  nlohmann::json describe() const;

 private:
  OutputKind kind_ = OutputKind::Map;
  std::vector<std::filesystem::path> files_;
  nlohmann::json metadata_;
  std::vector<MapFile> maps_;  // Map: one; ElevationStack: the slices in order
  std::optional<RadialProfile> radial_;
  std::vector<Rgb> fresnel_;
  std::optional<ShExpansion> sh_;
  double valueScale_ = 1.0;             // 1/pi for irradiance maps written before "irradiance_quantity" (they hold E)
  double minCos_ = 1.0, maxCos_ = 1.0;  // ElevationStack
  bool indexedByNormal_ = false, eyeSpace_ = false;
};

/// An opened output as a function of the lookup direction, for resampling (`brdfbake convert`):
/// lookup(d, cosView). For a Fresnel table, `cosView` must be absent and the function is F(n.v)
/// for the eye-space view +z: n = normalize(d + z), n.v = sqrt((1 + d.z) / 2) (what a sphere map of
/// the Fresnel term holds). Holds a reference: keep `output` alive.
class BakedOutputFunction final : public MapFunction {
 public:
  BakedOutputFunction(const BakedOutput& output, std::optional<double> cosView);
  Rgb evaluate(const Vec3& direction) const override;

 private:
  const BakedOutput& output_;
  std::optional<double> cosView_;
};

}  // namespace brdfbake
