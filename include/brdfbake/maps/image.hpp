#pragma once
/// @file
/// In-memory float RGBA images (row 0 is the top row) and the metadata every map carries.

#include <brdfbake/core/color.hpp>
#include <brdfbake/maps/parameterization.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace brdfbake {

/// A float RGBA image, row-major, row 0 at the top. Colours are linear; alpha is the texel's
/// coverage of the map's domain.
class Image {
 public:
  Image() = default;
  /// A width x height image filled with `fill`. Throws Error(InvalidArgument) for sizes < 1.
  Image(int width, int height, const Rgba& fill = Rgba::Zero());

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }

  Rgba at(int x, int y) const {
    const float* p = &pixels_[index(x, y)];
    return {p[0], p[1], p[2], p[3]};
  }
  void set(int x, int y, const Rgba& value) {
    float* p = &pixels_[index(x, y)];
    for (int c = 0; c < 4; ++c) p[c] = static_cast<float>(value[c]);
  }
  float* data() { return pixels_.data(); }
  const float* data() const { return pixels_.data(); }
  std::size_t index(int x, int y) const { return (static_cast<std::size_t>(y) * width_ + x) * 4; }

  /// Map metadata (see MapInfo); empty for a plain image.
  nlohmann::json metadata = nlohmann::json::object();

 private:
  int width_ = 0, height_ = 0;
  std::vector<float> pixels_;
};

/// metadata[key] when `metadata` is an object holding `key` as a value of T's JSON type, else
/// `fallback`: metadata comes from files, and a wrong type ("resolution": "8") must read as absent,
/// to be refused by name, never as nlohmann's type_error.
template <class T>
T metadataValue(const nlohmann::json& metadata, const char* key, T fallback) {
  if (!metadata.is_object()) return fallback;
  const auto it = metadata.find(key);
  if (it == metadata.end()) return fallback;
  if constexpr (std::is_same_v<T, nlohmann::json>) {
    return *it;
  } else if constexpr (std::is_same_v<T, std::string>) {
    return it->is_string() ? it->template get<std::string>() : fallback;
  } else {
    static_assert(std::is_integral_v<T>, "metadataValue reads JSON, strings and integers");
    if (!it->is_number_integer()) return fallback;
    const long long v = it->template get<long long>();
    return v >= std::numeric_limits<T>::min() && v <= std::numeric_limits<T>::max() ? static_cast<T>(v) : fallback;
  }
}

/// What a map file says about itself: written into every map (OpenEXR/TIFF/PNG attributes, or a
/// sidecar FILE.json where the format cannot hold them) and read back by `brdfbake info`.
struct MapInfo {
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 0;
  int conventionVersion = 0;
  nlohmann::json spec;  ///< the full map spec (material, lights, ...) it was made from

  nlohmann::json toJson() const;
  /// Reads the keys written by toJson(); throws Error(InvalidInput) naming what is missing.
  static MapInfo fromJson(const nlohmann::json& metadata);
};

/// Bilinear lookup at a map-frame direction, as a GPU's bilinear filter does it: texel centres at
/// +0.5, clamped to the direction's region (hemisphere, cube face), wrapped horizontally for
/// lat-long. Returns RGBA.
Rgba sampleBilinear(const Image& image, const Parameterization& map, const Vec3& direction);

/// The "parameterization" metadata written on a 1-D Fresnel table (fresnelTableImage).
inline constexpr const char* kFresnelTableParameterization = "fresnel_table";
/// True for "fresnel_table" and for "fresnel_profile", its name in files written before the rename
/// (still read).
bool isFresnelTableParameterization(const std::string& parameterization);

/// The Fresnel texture F(cos theta) (fresnelTable, entry i at cos theta = (i + 0.5) / N) as an
/// N x 1 image (alpha 1) whose metadata ("parameterization": "fresnel_table", "resolution",
/// "coordinate", "convention_version") lets BakedOutput (output/baked_output.hpp) read it back.
Image fresnelTableImage(const std::vector<Rgb>& table);

/// Linear lookup of a 1-D texture (a radial profile or a Fresnel table): `texels` centred at
/// s = (i + 0.5) / N, interpolated linearly and clamped at both ends, as a GPU's linear filter
/// with clamp-to-edge does. Throws Error(InvalidArgument) if `texels` is empty.
Rgb sampleLinear1d(const std::vector<Rgb>& texels, double s);

/// Bilinear lookup at continuous pixel coordinates inside one region.
Rgba sampleBilinear(const Image& image, const Vec2& pixel, const TexelRect& region, bool wrapX);

/// The four texels a bilinear lookup reads, in image coordinates (columns xa, xb; rows ya, yb),
/// and the weights of xb and yb: value = (1 - wy)((1 - wx) [xa, ya] + wx [xb, ya]) + wy (...yb).
struct BilinearTaps {
  int xa = 0, xb = 0, ya = 0, yb = 0;
  double wx = 0.0, wy = 0.0;
};
/// The texels sampleBilinear reads at `pixel` in `region` (clamped to it, wrapped for wrapX).
BilinearTaps bilinearTaps(const Vec2& pixel, const TexelRect& region, bool wrapX);
/// The texels sampleBilinear(image, map, direction) reads, for any image laid out by `map`.
BilinearTaps bilinearTaps(const Parameterization& map, const Vec3& direction);

/// The two texels sampleLinear1d reads (i0, i1 = i0 or i0 + 1) and the weight of i1.
struct LinearTaps {
  int i0 = 0, i1 = 0;
  double w = 0.0;
};
/// The texels of an N-texel 1-D texture (N >= 1) sampleLinear1d reads at s.
LinearTaps linearTaps(int texels, double s);

}  // namespace brdfbake
