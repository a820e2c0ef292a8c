// Texel encodings against bit patterns computed by hand from IEEE 754 binary16 and the Vulkan
// specification's RGB9E5 and unsigned 11/10-bit float definitions, and against the compiler's own
// binary16 conversions (_Float16, correctly rounded) where it has them.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace brdfbake {
namespace {

struct HalfCase {
  float value;
  std::uint16_t bits;
  const char* why;
};

// Each pattern worked out from sign | (exponent + 15) << 10 | mantissa.
const HalfCase kHalfCases[] = {
    {0.0f, 0x0000, "zero"},
    {-0.0f, 0x8000, "negative zero keeps its sign"},
    {1.0f, 0x3C00, "2^0: exponent 15"},
    {-2.0f, 0xC000, "sign, exponent 16"},
    {0.5f, 0x3800, "exponent 14"},
    {0.1f, 0x2E66, "1.6 * 2^-4: mantissa 0.6 * 1024 = 614.4 -> 614"},
    {1.0f / 3.0f, 0x3555, "1.333 * 2^-2: 341.33 -> 341"},
    {3.14159265f, 0x4248, "pi: 1.5708 * 2: mantissa 584.5 - a little -> 584"},
    {65504.0f, 0x7BFF, "the largest finite half"},
    {65519.0f, 0x7BFF, "below 65504 + half an ulp: rounds down"},
    {65520.0f, 0x7BFF, "would round to infinity: clamped"},
    {1e9f, 0x7BFF, "overflow: clamped, never infinity"},
    {-1e9f, 0xFBFF, "negative overflow: clamped"},
    {std::numeric_limits<float>::infinity(), 0x7BFF, "infinity clamped too"},
    {0x1p-14f, 0x0400, "the smallest normal"},
    {0x1p-24f, 0x0001, "the smallest subnormal"},
    {0x1p-25f, 0x0000, "half the smallest subnormal: a tie, to even (0)"},
    {0x1.8p-25f, 0x0001, "three quarters of it: rounds up"},
    {0x1.8p-24f, 0x0002, "1.5 subnormal steps: a tie, to even (2)"},
    {0x1.ffcp-15f, 0x0400, "just below 2^-14, rounding up into the smallest normal"},
    {1.0f + 0x1p-11f, 0x3C00, "a tie between 1 and 1 + 2^-10: to even"},
    {1.0f + 0x3p-11f, 0x3C02, "a tie between 0x3C01 and 0x3C02: to even"},
    {1.0f + 0x1p-11f + 0x1p-20f, 0x3C01, "just above the tie: up"},
    {2047.5f, 0x6800, "2047.5 -> 2048: the carry moves into the exponent"},
};

TEST(TexelFormat, HalfEncodingsMatchHandComputedBits) {
  for (const HalfCase& c : kHalfCases) {
    EXPECT_EQ(floatToHalf(c.value), c.bits) << c.value << ": " << c.why;
  }
}

TEST(TexelFormat, HalfDecodingMatchesHandComputedValues) {
  EXPECT_EQ(halfToFloat(0x3C00), 1.0f);
  EXPECT_EQ(halfToFloat(0xC000), -2.0f);
  EXPECT_EQ(halfToFloat(0x7BFF), 65504.0f);
  EXPECT_EQ(halfToFloat(0x0001), 0x1p-24f);
  EXPECT_EQ(halfToFloat(0x03FF), 1023.0f * 0x1p-24f);
  EXPECT_EQ(halfToFloat(0x2E66), 0.0999755859375f);
  EXPECT_TRUE(std::isinf(halfToFloat(0x7C00)));
  EXPECT_TRUE(std::isnan(halfToFloat(0x7E00)));
  EXPECT_TRUE(std::signbit(halfToFloat(0x8000)));
}

TEST(TexelFormat, NaNIsRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(floatToHalf(nan), Error);
  EXPECT_THROW(encodeRgb9e5(1.0f, nan, 0.0f), Error);
  EXPECT_THROW(encodeB10g11r11(nan, 0.0f, 0.0f), Error);
}

#if defined(__FLT16_MAX__) && !defined(__clang__)
// _Float16 conversions are correctly rounded (to nearest even) in GCC, in hardware or in libgcc.
std::uint16_t referenceHalf(float v) { return std::bit_cast<std::uint16_t>(static_cast<_Float16>(v)); }

TEST(TexelFormat, HalfEncodingAgreesWithTheCompilerAtEveryRoundingBoundary) {
  // For every finite half h: h itself, the midpoint to the next half and the floats either side
  // of it (where rounding decides), and both signs. Above 65504 the compiler gives infinity and we
  // clamp: those are checked by HalfEncodingsMatchHandComputedBits.
  int checked = 0;
  for (std::uint32_t bits = 0; bits < 0x7BFF; ++bits) {
    const double h = halfToFloat(static_cast<std::uint16_t>(bits));
    const double next = halfToFloat(static_cast<std::uint16_t>(bits + 1));
    const float mid = static_cast<float>(0.5 * (h + next));  // exact in float
    for (const float v : {static_cast<float>(h), mid, std::nextafter(mid, 0.0f), std::nextafter(mid, 1e6f)}) {
      for (const float s : {v, -v}) {
        ASSERT_EQ(floatToHalf(s), referenceHalf(s)) << "value " << s;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 200000);
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> any;
  for (int i = 0; i < 200000; ++i) {
    const float v = std::bit_cast<float>(any(rng));
    if (!std::isfinite(v) || std::abs(v) >= 65520.0f) continue;
    ASSERT_EQ(floatToHalf(v), referenceHalf(v)) << "value " << v;
  }
}

TEST(TexelFormat, HalfDecodingAgreesWithTheCompilerForEveryHalf) {
  for (std::uint32_t bits = 0; bits <= 0xFFFF; ++bits) {
    const float ours = halfToFloat(static_cast<std::uint16_t>(bits));
    const float reference = static_cast<float>(std::bit_cast<_Float16>(static_cast<std::uint16_t>(bits)));
    if (std::isnan(reference)) {
      ASSERT_TRUE(std::isnan(ours)) << bits;
    } else {
      ASSERT_EQ(std::bit_cast<std::uint32_t>(ours), std::bit_cast<std::uint32_t>(reference)) << bits;
    }
  }
}
#else
TEST(TexelFormat, HalfEncodingAgreesWithTheCompilerAtEveryRoundingBoundary) {
  GTEST_SKIP() << "this compiler has no _Float16 conversions to compare with (GCC 12 on x86-64 has)";
}
#endif

// RGB9E5, worked through the Vulkan specification's steps (N = 9, B = 15):
// exp' = max(-16, floor(log2 max_c)) + 1 + B; max_s = floor(max_c / 2^(exp' - B - N) + 0.5);
// exp_s = exp' + 1 if max_s = 512; each channel floor(c / 2^(exp_s - B - N) + 0.5).
TEST(TexelFormat, Rgb9e5MatchesTheSpecificationsAlgorithmByHand) {
  // (1, 1, 1): exp' = 0 + 16 = 16; mantissas 1 * 2^8 = 256; 256 | 256 << 9 | 256 << 18 | 16 << 27.
  EXPECT_EQ(encodeRgb9e5(1.0f, 1.0f, 1.0f), 0x84020100u);
  // Just below 1: exp' = 15, max_s = floor(0.9995 * 512 + 0.5) = 512 -> exp_s = 16, mantissas 256.
  EXPECT_EQ(encodeRgb9e5(0.9995f, 0.9995f, 0.9995f), 0x84020100u);
  // The largest, 65408 = 511 * 2^7: exponent 31, mantissas 511: every bit set.
  EXPECT_EQ(encodeRgb9e5(65408.0f, 65408.0f, 65408.0f), 0xFFFFFFFFu);
  // Clamped: 1e9 -> 65408; -5 -> 0.
  EXPECT_EQ(encodeRgb9e5(1e9f, -5.0f, 0.0f), 0xF80001FFu);
  EXPECT_EQ(encodeRgb9e5(0.0f, 0.0f, 0.0f), 0u);
  // (0.5, 0.25, 2): max 2, exp' = 1 + 16 = 17, step 2^-7: 64, 32, 256.
  EXPECT_EQ(encodeRgb9e5(0.5f, 0.25f, 2.0f), 64u | (32u << 9) | (256u << 18) | (17u << 27));
  // The smallest step: exp' = -16 + 16 = 0 -> step 2^-24; 2^-24 is mantissa 1.
  EXPECT_EQ(encodeRgb9e5(0x1p-24f, 0.0f, 0.0f), 1u);
  const Rgb back = decodeRgb9e5(0x84020100u);
  EXPECT_EQ(back[0], 1.0);
  EXPECT_EQ(decodeRgb9e5(0xFFFFFFFFu)[2], 65408.0);
}

// Unsigned 11-bit floats: exponent (bias 15) << 6 | mantissa; 10-bit: << 5.
TEST(TexelFormat, B10g11r11MatchesHandComputedBits) {
  // 1.0: exponent 15 -> 15 << 6 = 0x3C0 (red, green), 15 << 5 = 0x1E0 (blue, bits 22-31).
  EXPECT_EQ(encodeB10g11r11(1.0f, 1.0f, 1.0f), 0x781E03C0u);
  // (0.5, 2, 0): 14 << 6 = 0x380; 16 << 6 = 0x400, << 11.
  EXPECT_EQ(encodeB10g11r11(0.5f, 2.0f, 0.0f), 0x00200380u);
  // Largest finite: (30 << 6) | 63 = 0x7BF = 65024; (30 << 5) | 31 = 0x3DF = 64512.
  EXPECT_EQ(encodeB10g11r11(1e9f, 1e9f, 1e9f), 0xF7FDFFBFu);
  EXPECT_EQ(unsignedFloatToFloat(0x7BF, 6), kFloat11Max);
  EXPECT_EQ(unsignedFloatToFloat(0x3DF, 5), kFloat10Max);
  // Negative -> 0; smallest subnormal 2^-20 (11-bit) -> 1; a tie rounds to even.
  EXPECT_EQ(encodeB10g11r11(-1.0f, 0x1p-20f, 0.0f), 1u << 11);
  EXPECT_EQ(floatToUnsignedFloat(1.0f + 0x1p-7f, 6), 0x3C0u);             // tie between 0x3C0 and 0x3C1: even
  EXPECT_EQ(floatToUnsignedFloat(1.0f + 0x3p-7f, 6), 0x3C2u);             // tie between 0x3C1 and 0x3C2: even
  EXPECT_EQ(floatToUnsignedFloat(1.0f + 0x1p-7f + 0x1p-12f, 6), 0x3C1u);  // above the tie
  EXPECT_EQ(floatToUnsignedFloat(127.9f, 6), 22u << 6);  // rounds up to 128 = 2^7: exponent 7 + 15, mantissa 0
  const Rgb back = decodeB10g11r11(0x781E03C0u);
  EXPECT_EQ(back[0], 1.0);
  EXPECT_EQ(back[2], 1.0);
  EXPECT_TRUE(std::isinf(unsignedFloatToFloat(31u << 6, 6)));
}

TEST(TexelFormat, EveryUnsignedSmallFloatRoundTrips) {
  for (const int m : {5, 6}) {
    for (std::uint32_t bits = 0; bits < (31u << m); ++bits) {
      ASSERT_EQ(floatToUnsignedFloat(unsignedFloatToFloat(bits, m), m), bits) << m << " " << bits;
    }
  }
}

TEST(TexelFormat, EncodingTalliesWhatItChangedAndSaysSo) {
  const float texels[8] = {70000.0f, -1.0f, 2.0f, 0.5f, 1.0f, 1.0f, 1.0f, 1.0f};
  unsigned char out[8];
  EncodingTally tally;
  encodeTexels(texels, 2, TexelFormat::Rgb9e5, out, tally);
  EXPECT_EQ(tally.overflowed, 1u);
  EXPECT_EQ(tally.negative, 1u);
  EXPECT_EQ(tally.alphaNotOne, 1u);
  const auto notes = encodingNotes(tally, TexelFormat::Rgb9e5);
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_NE(notes[0].find("65408"), std::string::npos);
  EXPECT_NE(notes[1].find("stored as 0"), std::string::npos);
  EXPECT_NE(notes[2].find("alpha"), std::string::npos);
  float back[8];
  decodeTexels(out, 2, TexelFormat::Rgb9e5, back);
  EXPECT_EQ(back[0], 65408.0f);
  EXPECT_EQ(back[1], 0.0f);
  EXPECT_EQ(back[3], 1.0f);
}

TEST(TexelFormat, NamesRoundTripAndUnknownNamesAreListed) {
  for (const TexelFormat f : {TexelFormat::Rgba16Float, TexelFormat::Rgba32Float, TexelFormat::Rgb16Float,
                              TexelFormat::Rgb32Float, TexelFormat::Rgb9e5, TexelFormat::B10g11r11}) {
    EXPECT_EQ(parseTexelFormat(toString(f)), f);
  }
  try {
    parseTexelFormat("rgba8");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rgba16f"), std::string::npos);
  }
}

}  // namespace
}  // namespace brdfbake
