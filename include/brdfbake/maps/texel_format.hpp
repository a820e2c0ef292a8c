#pragma once
/// @file
/// The float texel encodings the texture containers (texture.hpp: KTX2, KTX1, DDS) hold, and
/// their exact conversions: IEEE 754 binary16 (half), the shared-exponent RGB9E5 and the packed
/// unsigned 11/11/10-bit floats. Encoders round to nearest, ties to even; they never produce
/// infinity or NaN: a magnitude above the format's largest finite value becomes that value, and the
/// unsigned formats store negative values as 0. NaN is refused (Error(InvalidArgument)).

#include <brdfbake/core/color.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// How a texel is stored. The RGB formats drop alpha (read back as 1).
enum class TexelFormat {
  Rgba16Float,  ///< 4 x binary16 (Vulkan R16G16B16A16_SFLOAT, DXGI R16G16B16A16_FLOAT, GL RGBA16F); the default
  Rgba32Float,  ///< 4 x binary32 (R32G32B32A32_SFLOAT)
  Rgb16Float,   ///< 3 x binary16 (R16G16B16_SFLOAT, GL RGB16F; no DXGI format, so no DDS)
  Rgb32Float,   ///< 3 x binary32 (R32G32B32_SFLOAT)
  Rgb9e5,       ///< 9-bit mantissas and a shared 5-bit exponent in 32 bits (E5B9G9R9_UFLOAT_PACK32)
  B10g11r11,    ///< unsigned 11-, 11-, 10-bit floats in 32 bits (B10G11R11_UFLOAT_PACK32)
};

/// "rgba16f", "rgba32f", "rgb16f", "rgb32f", "rgb9e5", "rg11b10f".
std::string_view toString(TexelFormat format);
/// The inverse of toString; throws Error(InvalidArgument) listing the names.
TexelFormat parseTexelFormat(std::string_view name);
/// Bytes per texel: 8, 16, 6, 12, 4, 4.
int bytesPerTexel(TexelFormat format);
/// True for the two RGBA formats.
bool hasAlpha(TexelFormat format);
/// True for the formats that hold no negative value (Rgb9e5, B10g11r11).
bool isUnsigned(TexelFormat format);

/// The largest finite binary16, 65504 = (2 - 2^-10) 2^15.
inline constexpr float kHalfMax = 65504.0f;
/// The largest value RGB9E5 holds, 65408 = (511 / 512) 2^16 (Vulkan spec, "Shared Exponent Conversion").
inline constexpr float kRgb9e5Max = 65408.0f;
/// The largest finite unsigned 11-bit float, (2 - 2^-6) 2^15 = 65024, and 10-bit, (2 - 2^-5) 2^15 = 64512.
inline constexpr float kFloat11Max = 65024.0f;
inline constexpr float kFloat10Max = 64512.0f;

/// The binary16 nearest to `value` (ties to even); |value| > 65504 gives +-65504 (also for
/// infinity), never infinity. Throws Error(InvalidArgument) for NaN.
std::uint16_t floatToHalf(float value);
/// The value of a binary16 (infinity and NaN decode as such; readers refuse them).
float halfToFloat(std::uint16_t bits);

/// RGB9E5 by the Vulkan specification's algorithm ("Shared Exponent Conversion", as
/// EXT_texture_shared_exponent): each channel clamped to [0, 65408], exponent from the largest,
/// mantissas rounded to nearest. Red in bits 0-8, green 9-17, blue 18-26, exponent 27-31.
/// Throws Error(InvalidArgument) for NaN.
std::uint32_t encodeRgb9e5(float red, float green, float blue);
/// mantissa * 2^(exponent - 24) per channel.
Rgb decodeRgb9e5(std::uint32_t packed);

/// Unsigned 11-bit (5-bit exponent, bias 15, 6-bit mantissa) and 10-bit (5-bit mantissa) floats:
/// nearest, ties to even; negative -> 0; above the largest finite -> the largest finite.
/// Throws Error(InvalidArgument) for NaN.
std::uint32_t floatToUnsignedFloat(float value, int mantissaBits);
/// The value of an unsigned small float (exponent 31 decodes as infinity or NaN).
float unsignedFloatToFloat(std::uint32_t bits, int mantissaBits);
/// Red (11 bits) in bits 0-10, green (11) in 11-21, blue (10) in 22-31.
std::uint32_t encodeB10g11r11(float red, float green, float blue);
Rgb decodeB10g11r11(std::uint32_t packed);

/// What encoding changed beyond rounding, for the write report.
struct EncodingTally {
  std::uint64_t overflowed = 0;   ///< channel values above the format's largest finite value, stored as it
  std::uint64_t negative = 0;     ///< negative channel values stored as 0 (unsigned formats)
  std::uint64_t alphaNotOne = 0;  ///< texels whose alpha was not 1, dropped by an RGB format
};

/// Encodes `count` RGBA float texels (4 floats each) into `out` (count * bytesPerTexel bytes,
/// little-endian), counting into `tally`. Throws Error(InvalidArgument) for NaN.
void encodeTexels(const float* rgba, std::size_t count, TexelFormat format, unsigned char* out, EncodingTally& tally);
/// Decodes `count` texels from `in` (little-endian) into RGBA floats (alpha 1 for RGB formats).
/// Values are decoded as stored: infinity and NaN included (callers check).
void decodeTexels(const unsigned char* in, std::size_t count, TexelFormat format, float* rgba);

/// Notes for a write report, e.g. "3 values above 65504 (the largest finite half) stored as 65504".
std::vector<std::string> encodingNotes(const EncodingTally& tally, TexelFormat format);

}  // namespace brdfbake
