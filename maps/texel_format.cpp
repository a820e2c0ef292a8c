// Float texel encodings: binary16, RGB9E5, unsigned 11/10-bit floats (texel_format.hpp).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace brdfbake {
namespace {

struct FormatRow {
  TexelFormat format;
  const char* name;
  int bytes;
  bool alpha;
  bool unsignedOnly;
};
constexpr FormatRow kFormats[] = {
    {TexelFormat::Rgba16Float, "rgba16f", 8, true, false}, {TexelFormat::Rgba32Float, "rgba32f", 16, true, false},
    {TexelFormat::Rgb16Float, "rgb16f", 6, false, false},  {TexelFormat::Rgb32Float, "rgb32f", 12, false, false},
    {TexelFormat::Rgb9e5, "rgb9e5", 4, false, true},       {TexelFormat::B10g11r11, "rg11b10f", 4, false, true},
};

const FormatRow& row(TexelFormat format) {
  for (const FormatRow& r : kFormats)
    if (r.format == format) return r;
  throw Error(Error::Kind::InvalidArgument, "unknown texel format");
}

void refuseNaN(float value) {
  if (std::isnan(value)) {
    throw Error(Error::Kind::InvalidArgument, "refusing to encode NaN: brdfbake never writes NaN or infinity");
  }
}

// x rounded to the nearest integer, ties to even; exact for |x| < 2^52.
double roundHalfEven(double x) {
  double f = std::floor(x);
  const double d = x - f;
  if (d > 0.5 || (d == 0.5 && std::fmod(f, 2.0) != 0.0)) f += 1.0;
  return f;
}

void storeU16(unsigned char* out, std::uint16_t v) {
  out[0] = static_cast<unsigned char>(v & 0xFF);
  out[1] = static_cast<unsigned char>(v >> 8);
}
void storeU32(unsigned char* out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<unsigned char>((v >> (8 * i)) & 0xFF);
}
std::uint16_t loadU16(const unsigned char* in) { return static_cast<std::uint16_t>(in[0] | (in[1] << 8)); }
std::uint32_t loadU32(const unsigned char* in) {
  return static_cast<std::uint32_t>(in[0]) | (static_cast<std::uint32_t>(in[1]) << 8) |
         (static_cast<std::uint32_t>(in[2]) << 16) | (static_cast<std::uint32_t>(in[3]) << 24);
}

}  // namespace

std::string_view toString(TexelFormat format) { return row(format).name; }

TexelFormat parseTexelFormat(std::string_view name) {
  std::array<TexelFormat, std::size(kFormats)> formats{};
  for (std::size_t i = 0; i < formats.size(); ++i) formats[i] = kFormats[i].format;
  return parseByName(name, formats, "texel format");
}

int bytesPerTexel(TexelFormat format) { return row(format).bytes; }
bool hasAlpha(TexelFormat format) { return row(format).alpha; }
bool isUnsigned(TexelFormat format) { return row(format).unsignedOnly; }

std::uint16_t floatToHalf(float value) {
  refuseNaN(value);
  const std::uint32_t x = std::bit_cast<std::uint32_t>(value);
  const std::uint16_t sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  const std::uint32_t ax = x & 0x7FFFFFFFu;
  // 65520 = 65504 + half an ulp: from there on, rounding to nearest would give infinity.
  if (ax >= 0x477FF000u) return static_cast<std::uint16_t>(sign | 0x7BFFu);
  if (ax < 0x38800000u) {
    // Below 2^-14: a subnormal half m 2^-24. Scaling by 2^24 is exact; m = 1024 is the smallest normal.
    const double m = roundHalfEven(static_cast<double>(std::bit_cast<float>(ax)) * 16777216.0);
    return static_cast<std::uint16_t>(sign | static_cast<std::uint16_t>(m));
  }
  const std::uint32_t exponent = (ax >> 23) - 127 + 15;  // 1 .. 30
  const std::uint32_t mantissa = ax & 0x7FFFFFu;
  std::uint32_t h = (exponent << 10) | (mantissa >> 13);
  const std::uint32_t rest = mantissa & 0x1FFFu;             // the 13 bits dropped
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // a carry moves into the exponent, as it should
  return static_cast<std::uint16_t>(sign | h);
}

float halfToFloat(std::uint16_t bits) {
  const float sign = (bits & 0x8000u) ? -1.0f : 1.0f;
  const int exponent = (bits >> 10) & 0x1F;
  const int mantissa = bits & 0x3FF;
  if (exponent == 0) return sign * std::ldexp(static_cast<float>(mantissa), -24);
  if (exponent == 31) return mantissa == 0 ? sign * INFINITY : NAN;
  return sign * std::ldexp(static_cast<float>(1024 + mantissa), exponent - 25);
}

std::uint32_t encodeRgb9e5(float red, float green, float blue) {
  refuseNaN(red), refuseNaN(green), refuseNaN(blue);
  constexpr int N = 9, B = 15;
  auto clampChannel = [](float v) { return std::clamp(static_cast<double>(v), 0.0, static_cast<double>(kRgb9e5Max)); };
  const double r = clampChannel(red), g = clampChannel(green), b = clampChannel(blue);
  const double maxC = std::max({r, g, b});
  // floor(log2(max_c)), and -B - 1 for max_c = 0 (the spec's max(-B - 1, ...)).
  int floorLog2 = -B - 1;
  if (maxC > 0.0) {
    int e = 0;
    std::frexp(maxC, &e);  // maxC = f 2^e, f in [0.5, 1)
    floorLog2 = std::max(-B - 1, e - 1);
  }
  int exponent = floorLog2 + 1 + B;
  const double maxS = std::floor(std::ldexp(maxC, -(exponent - B - N)) + 0.5);
  if (maxS == 512.0) ++exponent;
  auto mantissa = [&](double v) {
    return static_cast<std::uint32_t>(std::floor(std::ldexp(v, -(exponent - B - N)) + 0.5));
  };
  return mantissa(r) | (mantissa(g) << 9) | (mantissa(b) << 18) | (static_cast<std::uint32_t>(exponent) << 27);
}

Rgb decodeRgb9e5(std::uint32_t packed) {
  const int exponent = static_cast<int>(packed >> 27) - 15 - 9;
  return {std::ldexp(static_cast<double>(packed & 0x1FFu), exponent),
          std::ldexp(static_cast<double>((packed >> 9) & 0x1FFu), exponent),
          std::ldexp(static_cast<double>((packed >> 18) & 0x1FFu), exponent)};
}

std::uint32_t floatToUnsignedFloat(float value, int mantissaBits) {
  refuseNaN(value);
  require(mantissaBits == 5 || mantissaBits == 6, "unsigned small floats have 5 or 6 mantissa bits");
  const std::uint32_t one = 1u << mantissaBits;
  const std::uint32_t largest = (30u << mantissaBits) | (one - 1u);
  if (!(value > 0.0f)) return 0u;  // zero and negative values
  if (std::isinf(value)) return largest;
  const double v = value;
  int e = 0;
  std::frexp(v, &e);
  int exponent = e - 1;  // v = q 2^exponent, q in [1, 2)
  if (exponent < -14) {
    // Subnormal: q 2^(-14 - m); q = 2^m is the smallest normal and packs as exponent 1.
    return static_cast<std::uint32_t>(roundHalfEven(std::ldexp(v, 14 + mantissaBits)));
  }
  double q = roundHalfEven(std::ldexp(v, mantissaBits - exponent));  // in [2^m, 2^(m+1)]
  if (q == 2.0 * one) q = one, ++exponent;
  if (exponent + 15 > 30) return largest;
  return (static_cast<std::uint32_t>(exponent + 15) << mantissaBits) | (static_cast<std::uint32_t>(q) - one);
}

float unsignedFloatToFloat(std::uint32_t bits, int mantissaBits) {
  const std::uint32_t mantissa = bits & ((1u << mantissaBits) - 1u);
  const int exponent = static_cast<int>((bits >> mantissaBits) & 0x1Fu);
  if (exponent == 0) return std::ldexp(static_cast<float>(mantissa), -14 - mantissaBits);
  if (exponent == 31) return mantissa == 0 ? INFINITY : NAN;
  return std::ldexp(static_cast<float>((1u << mantissaBits) + mantissa), exponent - 15 - mantissaBits);
}

std::uint32_t encodeB10g11r11(float red, float green, float blue) {
  return floatToUnsignedFloat(red, 6) | (floatToUnsignedFloat(green, 6) << 11) | (floatToUnsignedFloat(blue, 5) << 22);
}

Rgb decodeB10g11r11(std::uint32_t packed) {
  return {unsignedFloatToFloat(packed & 0x7FFu, 6), unsignedFloatToFloat((packed >> 11) & 0x7FFu, 6),
          unsignedFloatToFloat((packed >> 22) & 0x3FFu, 5)};
}

void encodeTexels(const float* rgba, std::size_t count, TexelFormat format, unsigned char* out, EncodingTally& tally) {
  const int bytes = bytesPerTexel(format);
  const bool alpha = hasAlpha(format);
  for (std::size_t i = 0; i < count; ++i, rgba += 4, out += bytes) {
    const int channels = alpha ? 4 : 3;
    if (!alpha && rgba[3] != 1.0f) ++tally.alphaNotOne;
    switch (format) {
      case TexelFormat::Rgba16Float:
      case TexelFormat::Rgb16Float:
        for (int c = 0; c < channels; ++c) {
          if (std::abs(rgba[c]) > kHalfMax) ++tally.overflowed;
          storeU16(out + 2 * c, floatToHalf(rgba[c]));
        }
        break;
      case TexelFormat::Rgba32Float:
      case TexelFormat::Rgb32Float:
        for (int c = 0; c < channels; ++c) {
          refuseNaN(rgba[c]);
          storeU32(out + 4 * c, std::bit_cast<std::uint32_t>(rgba[c]));
        }
        break;
      case TexelFormat::Rgb9e5:
        for (int c = 0; c < 3; ++c) tally.overflowed += rgba[c] > kRgb9e5Max, tally.negative += rgba[c] < 0.0f;
        storeU32(out, encodeRgb9e5(rgba[0], rgba[1], rgba[2]));
        break;
      case TexelFormat::B10g11r11:
        for (int c = 0; c < 3; ++c) {
          tally.overflowed += rgba[c] > (c < 2 ? kFloat11Max : kFloat10Max);
          tally.negative += rgba[c] < 0.0f;
        }
        storeU32(out, encodeB10g11r11(rgba[0], rgba[1], rgba[2]));
        break;
    }
  }
}

void decodeTexels(const unsigned char* in, std::size_t count, TexelFormat format, float* rgba) {
  const int bytes = bytesPerTexel(format);
  for (std::size_t i = 0; i < count; ++i, in += bytes, rgba += 4) {
    rgba[3] = 1.0f;
    switch (format) {
      case TexelFormat::Rgba16Float:
      case TexelFormat::Rgb16Float:
        for (int c = 0; c < bytes / 2; ++c) rgba[c] = halfToFloat(loadU16(in + 2 * c));
        break;
      case TexelFormat::Rgba32Float:
      case TexelFormat::Rgb32Float:
        for (int c = 0; c < bytes / 4; ++c) rgba[c] = std::bit_cast<float>(loadU32(in + 4 * c));
        break;
      case TexelFormat::Rgb9e5:
      case TexelFormat::B10g11r11: {
        const std::uint32_t packed = loadU32(in);
        const Rgb v = format == TexelFormat::Rgb9e5 ? decodeRgb9e5(packed) : decodeB10g11r11(packed);
        for (int c = 0; c < 3; ++c) rgba[c] = static_cast<float>(v[c]);
        break;
      }
    }
  }
}

std::vector<std::string> encodingNotes(const EncodingTally& tally, TexelFormat format) {
  std::vector<std::string> notes;
  const std::string name(toString(format));
  if (tally.overflowed > 0) {
    const char* largest = format == TexelFormat::Rgb9e5      ? "65408"
                          : format == TexelFormat::B10g11r11 ? "65024 (64512 for blue)"
                                                             : "65504";
    notes.push_back(name + ": " + std::to_string(tally.overflowed) + " channel value(s) above the largest finite " +
                    largest + " stored as it (never as infinity)");
  }
  if (tally.negative > 0) {
    notes.push_back(name + " holds no negative values: " + std::to_string(tally.negative) +
                    " negative channel value(s) stored as 0");
  }
  if (!hasAlpha(format)) {
    notes.push_back(name + " holds RGB only: alpha (coverage) dropped" +
                    (tally.alphaNotOne > 0 ? " (" + std::to_string(tally.alphaNotOne) + " texel(s) had alpha != 1)"
                                           : std::string()) +
                    "; read back as 1");
  }
  return notes;
}

}  // namespace brdfbake
