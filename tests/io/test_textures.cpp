// Texture containers (texture.hpp): round trips within each format's precision, the bytes each
// specification prescribes, and malformed files refused with the file named.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/texture.hpp>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "test_support.hpp"

namespace brdfbake {
namespace {

constexpr TexelFormat kFormats[] = {TexelFormat::Rgba16Float, TexelFormat::Rgba32Float, TexelFormat::Rgb16Float,
                                    TexelFormat::Rgb32Float,  TexelFormat::Rgb9e5,      TexelFormat::B10g11r11};
constexpr TextureContainer kContainers[] = {TextureContainer::Ktx2, TextureContainer::Ktx1, TextureContainer::Dds};

using TexelFunction = std::function<Rgba(int level, int face, int x, int y)>;

Texture makeTexture(int width, int height, int faces, int levels, const TexelFunction& value) {
  Texture texture;
  for (int k = 0; k < levels; ++k) {
    texture.levels.emplace_back();
    for (int f = 0; f < faces; ++f) {
      Image image(std::max(1, width >> k), std::max(1, height >> k));
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) image.set(x, y, value(k, f, x, y));
      texture.levels.back().push_back(std::move(image));
    }
  }
  return texture;
}

// Distinct values per level, face, texel and channel, spanning several octaves; negative ones
// only where the format is signed.
Rgba testValue(int k, int f, int x, int y, bool signedValues) {
  Rgba v;
  for (int c = 0; c < 4; ++c) {
    const double magnitude = std::ldexp(1.0 + 0.37 * ((x + 3 * y + 5 * c) % 7), (k + f + c) % 9 - 4);
    v[c] = (signedValues && (x + y + c) % 3 == 0) ? -magnitude : magnitude;
  }
  v[3] = 0.25 * ((x + y) % 4);  // coverage-like
  return v;
}

// How far a stored value may be from the written one, from each format's definition alone.
double tolerance(TexelFormat format, const Rgba& written, int c) {
  const double v = std::abs(written[c]);
  switch (format) {
    case TexelFormat::Rgba32Float:
    case TexelFormat::Rgb32Float:
      return 0.0;
    case TexelFormat::Rgba16Float:
    case TexelFormat::Rgb16Float:
      return v * 0x1p-11 + 0x1p-25;  // half an ulp of an 11-bit significand
    case TexelFormat::Rgb9e5:
      return written.head<3>().maxCoeff() * 0x1p-8;  // half a step of 9 bits shared with the largest
    case TexelFormat::B10g11r11:
      return v * (c < 2 ? 0x1p-7 : 0x1p-6);  // half an ulp of a 7- or 6-bit significand
  }
  return 0.0;
}

TEST(Textures, RoundTripEveryFormatInEveryContainerWithinItsPrecision) {
  for (const TextureContainer container : kContainers) {
    for (const TexelFormat format : kFormats) {
      for (const int faces : {1, 6}) {
        SCOPED_TRACE(std::string(toString(container)) + " " + std::string(toString(format)) + " faces " +
                     std::to_string(faces));
        const bool signedValues = !isUnsigned(format);
        const int w = faces == 6 ? 8 : 12, h = 8;
        const Texture texture = makeTexture(
            w, h, faces, 4, [&](int k, int f, int x, int y) { return testValue(k, f, x, y, signedValues); });
        if (!texelFormatProblem(container, format).empty()) {
          EXPECT_THROW(encodeTexture(texture, container, format, "t"), Error);
          continue;
        }
        const EncodedTexture encoded = encodeTexture(texture, container, format, "t");
        const Texture back = decodeTexture(encoded.bytes, "t");
        ASSERT_EQ(back.levelCount(), 4);
        ASSERT_EQ(back.faceCount(), faces);
        for (int k = 0; k < 4; ++k)
          for (int f = 0; f < faces; ++f) {
            const Image& a = texture.levels[k][f];
            const Image& b = back.levels[k][f];
            ASSERT_EQ(b.width(), a.width());
            ASSERT_EQ(b.height(), a.height());
            for (int y = 0; y < a.height(); ++y)
              for (int x = 0; x < a.width(); ++x) {
                const Rgba written = a.at(x, y), read = b.at(x, y);
                for (int c = 0; c < 3; ++c)
                  ASSERT_NEAR(read[c], written[c], tolerance(format, written, c))
                      << "level " << k << " face " << f << " texel " << x << "," << y << " channel " << c;
                ASSERT_EQ(read[3], hasAlpha(format) ? written[3] : 1.0);  // quarters are exact in half
              }
          }
      }
    }
  }
}

TEST(Textures, MetadataAndWriterTravelInKtxKeyValueData) {
  Texture texture = makeTexture(4, 4, 1, 1, [](int, int, int x, int y) { return Rgba(x, y, 1, 1); });
  texture.metadata = {{"parameterization", "sphere"}, {"level_values", {{{"roughness", 0.5}}}}};
  for (const TextureContainer container : {TextureContainer::Ktx2, TextureContainer::Ktx1}) {
    const TextureHeader header =
        readTextureHeader(encodeTexture(texture, container, TexelFormat::Rgba16Float).bytes, "t");
    EXPECT_EQ(header.metadata, texture.metadata);
    ASSERT_EQ(header.keyValues.size(), 3u);
    bool writer = false;
    for (const auto& [key, value] : header.keyValues)
      writer = writer || (key == "KTXwriter" && value.rfind("brdfbake ", 0) == 0);
    EXPECT_TRUE(writer);
  }
}

// ---- the bytes each specification prescribes ----------------------------------------------------

std::uint32_t u32At(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 4);  // little-endian host (x86-64, as CI)
  return v;
}
std::uint64_t u64At(const std::string& bytes, std::size_t offset) {
  std::uint64_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 8);
  return v;
}

TEST(Textures, Ktx2HeaderIndexAndDescriptorFollowTheSpecification) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int, int) { return Rgba(k, f, 0.5, 1); });
  const std::string bytes = encodeTexture(cube, TextureContainer::Ktx2, TexelFormat::Rgba16Float).bytes;
  EXPECT_EQ(bytes.substr(0, 12), std::string("\xABKTX 20\xBB\r\n\x1A\n", 12));
  EXPECT_EQ(u32At(bytes, 12), 97u);  // VK_FORMAT_R16G16B16A16_SFLOAT
  EXPECT_EQ(u32At(bytes, 16), 2u);   // typeSize: bytes of one component
  EXPECT_EQ(u32At(bytes, 20), 4u);
  EXPECT_EQ(u32At(bytes, 24), 4u);
  EXPECT_EQ(u32At(bytes, 28), 0u);  // pixelDepth
  EXPECT_EQ(u32At(bytes, 32), 0u);  // layerCount
  EXPECT_EQ(u32At(bytes, 36), 6u);  // faceCount
  EXPECT_EQ(u32At(bytes, 40), 3u);  // levelCount
  EXPECT_EQ(u32At(bytes, 44), 0u);  // supercompression none
  const std::uint32_t dfdOffset = u32At(bytes, 48), dfdLength = u32At(bytes, 52);
  EXPECT_EQ(dfdOffset, 80u + 3 * 24);
  EXPECT_EQ(dfdLength, 4u + 24 + 4 * 16);
  EXPECT_EQ(u32At(bytes, 56), dfdOffset + dfdLength);  // key/value data right after the descriptor
  EXPECT_EQ(u64At(bytes, 64), 0u);                     // no supercompression global data
  EXPECT_EQ(u64At(bytes, 72), 0u);
  // The basic descriptor block (Khronos Data Format 1.3, section 5), word by word.
  const std::uint32_t expectedDfd[] = {
      92,
      0,
      2u | (88u << 16),
      0x00010101u,
      0,
      8,
      0,
      0u | (15u << 16) | (0xC0u << 24),
      0,
      0xBF800000u,
      0x3F800000u,  // R: bits 0-15, float | signed
      16u | (15u << 16) | (0xC1u << 24),
      0,
      0xBF800000u,
      0x3F800000u,  // G
      32u | (15u << 16) | (0xC2u << 24),
      0,
      0xBF800000u,
      0x3F800000u,  // B
      48u | (15u << 16) | (0xCFu << 24),
      0,
      0xBF800000u,
      0x3F800000u,  // A: channel 15
  };
  for (std::size_t i = 0; i < std::size(expectedDfd); ++i)
    EXPECT_EQ(u32At(bytes, dfdOffset + 4 * i), expectedDfd[i]) << i;
  // Levels: smallest first in the file, each 8-byte aligned (lcm(8, 4)), 6 faces of w^2 x 8 bytes.
  std::uint64_t previousOffset = bytes.size();
  for (int k = 0; k < 3; ++k) {
    const std::uint64_t offset = u64At(bytes, 80 + 24 * k), length = u64At(bytes, 88 + 24 * k);
    const std::uint64_t n = 4 >> k;
    EXPECT_EQ(length, 6 * n * n * 8) << k;
    EXPECT_EQ(u64At(bytes, 96 + 24 * k), length) << k;
    EXPECT_EQ(offset % 8, 0u) << k;
    EXPECT_LT(offset, previousOffset) << "level " << k << " must come before level " << k - 1;
    EXPECT_LE(offset + length, previousOffset);
    previousOffset = offset;
  }
  EXPECT_EQ(u64At(bytes, 80) + u64At(bytes, 88), bytes.size());  // level 0 ends the file
  // Level 2 (1 x 1), face -X (1): (2, 1, 0.5, 1) as halves 0x4000 0x3C00 0x3800 0x3C00.
  const std::uint64_t face1 = u64At(bytes, 80 + 48) + 8;
  EXPECT_EQ(u64At(bytes, face1), 0x3C0038003C004000ull);
}

TEST(Textures, Ktx2DescriptorsOfThePackedFormats) {
  const Texture t = makeTexture(2, 2, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  const std::string e5 = encodeTexture(t, TextureContainer::Ktx2, TexelFormat::Rgb9e5).bytes;
  EXPECT_EQ(u32At(e5, 12), 123u);  // VK_FORMAT_E5B9G9R9_UFLOAT_PACK32
  EXPECT_EQ(u32At(e5, 16), 4u);    // typeSize of a _PACK32 format
  const std::uint32_t d = u32At(e5, 48);
  EXPECT_EQ(u32At(e5, d), 4u + 24 + 6 * 16);
  EXPECT_EQ(u32At(e5, d + 20), 4u);  // bytesPlane0
  // Red mantissa bits 0-8 (upper 8448), red exponent bits 27-31 (bias 15, max 31), green, blue.
  const std::uint32_t samples[6][4] = {{0u | (8u << 16), 0, 0, 8448},
                                       {27u | (4u << 16) | (0x20u << 24), 0, 15, 31},
                                       {9u | (8u << 16) | (1u << 24), 0, 0, 8448},
                                       {27u | (4u << 16) | (0x21u << 24), 0, 15, 31},
                                       {18u | (8u << 16) | (2u << 24), 0, 0, 8448},
                                       {27u | (4u << 16) | (0x22u << 24), 0, 15, 31}};
  for (int s = 0; s < 6; ++s)
    for (int w = 0; w < 4; ++w) EXPECT_EQ(u32At(e5, d + 28 + 16 * s + 4 * w), samples[s][w]) << s << " " << w;
  EXPECT_EQ(u32At(e5, static_cast<std::size_t>(u64At(e5, 80))), 0x84020100u);  // (1, 1, 1), see TexelFormat
  const std::string rg = encodeTexture(t, TextureContainer::Ktx2, TexelFormat::B10g11r11).bytes;
  EXPECT_EQ(u32At(rg, 12), 122u);  // VK_FORMAT_B10G11R11_UFLOAT_PACK32
  const std::uint32_t r = u32At(rg, 48);
  EXPECT_EQ(u32At(rg, r + 28), 0u | (10u << 16) | (0x80u << 24));   // red: 11 bits at 0, unsigned float
  EXPECT_EQ(u32At(rg, r + 44), 11u | (10u << 16) | (0x81u << 24));  // green: 11 bits at 11
  EXPECT_EQ(u32At(rg, r + 60), 22u | (9u << 16) | (0x82u << 24));   // blue: 10 bits at 22
  EXPECT_EQ(u32At(rg, r + 36), 0u);                                 // sampleLower 0.0f
  EXPECT_EQ(u32At(rg, r + 40), 0x3F800000u);                        // sampleUpper 1.0f
}

TEST(Textures, DdsHeaderFollowsTheSpecification) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int, int) { return Rgba(k, f, 0.5, 1); });
  const std::string bytes = encodeTexture(cube, TextureContainer::Dds, TexelFormat::Rgba16Float).bytes;
  EXPECT_EQ(bytes.substr(0, 4), "DDS ");
  EXPECT_EQ(u32At(bytes, 4), 124u);
  EXPECT_EQ(u32At(bytes, 8) & 0x1007u, 0x1007u);    // CAPS | HEIGHT | WIDTH | PIXELFORMAT
  EXPECT_EQ(u32At(bytes, 8) & 0x20000u, 0x20000u);  // MIPMAPCOUNT
  EXPECT_EQ(u32At(bytes, 12), 4u);                  // height
  EXPECT_EQ(u32At(bytes, 16), 4u);                  // width
  EXPECT_EQ(u32At(bytes, 20), 4u * 8);              // pitch: bytes of a row
  EXPECT_EQ(u32At(bytes, 28), 3u);                  // mip levels
  EXPECT_EQ(u32At(bytes, 76), 32u);                 // DDS_PIXELFORMAT size
  EXPECT_EQ(u32At(bytes, 80), 4u);                  // DDPF_FOURCC
  EXPECT_EQ(bytes.substr(84, 4), "DX10");
  EXPECT_EQ(u32At(bytes, 108), 0x1000u | 0x400000u | 0x8u);  // TEXTURE | MIPMAP | COMPLEX
  EXPECT_EQ(u32At(bytes, 112), 0xFE00u);                     // CUBEMAP | all six faces
  EXPECT_EQ(u32At(bytes, 128), 10u);                         // DXGI_FORMAT_R16G16B16A16_FLOAT
  EXPECT_EQ(u32At(bytes, 132), 3u);                          // TEXTURE2D
  EXPECT_EQ(u32At(bytes, 136), 4u);                          // RESOURCE_MISC_TEXTURECUBE
  EXPECT_EQ(u32At(bytes, 140), 1u);                          // arraySize: one cube
  // Faces outer, levels inner: 6 x (16 + 4 + 1) texels of 8 bytes after the 148-byte headers.
  EXPECT_EQ(bytes.size(), 148u + 6 * 21 * 8);
  // Face +Y (2), level 1 (2 x 2): (1, 2, 0.5, 1) -> halves 0x3C00 0x4000 0x3800 0x3C00.
  EXPECT_EQ(u64At(bytes, 148 + (2 * 21 + 16) * 8), 0x3C00380040003C00ull);
}

TEST(Textures, Ktx1HeaderAndCubeImageSizeFollowTheSpecification) {
  const Texture cube = makeTexture(4, 4, 6, 2, [](int k, int f, int, int) { return Rgba(k, f, 0.5, 1); });
  const std::string bytes = encodeTexture(cube, TextureContainer::Ktx1, TexelFormat::Rgba32Float).bytes;
  EXPECT_EQ(bytes.substr(0, 12), std::string("\xABKTX 11\xBB\r\n\x1A\n", 12));
  const std::uint32_t expected[] = {0x04030201u,
                                    0x1406u /* GL_FLOAT */,
                                    4,
                                    0x1908u /* GL_RGBA */,
                                    0x8814u /* GL_RGBA32F */,
                                    0x1908u,
                                    4,
                                    4,
                                    0,
                                    0,
                                    6,
                                    2};
  for (std::size_t i = 0; i < std::size(expected); ++i) EXPECT_EQ(u32At(bytes, 12 + 4 * i), expected[i]) << i;
  const std::uint32_t kvd = u32At(bytes, 60);
  // For a cube map, imageSize is the size of one face (KTX 1.1, "imageSize").
  EXPECT_EQ(u32At(bytes, 64 + kvd), 4u * 4 * 16);
  EXPECT_EQ(u32At(bytes, 64 + kvd + 4 + 6 * 256), 2u * 2 * 16);
  EXPECT_EQ(bytes.size(), 64u + kvd + 4 + 6 * 256 + 4 + 6 * 64);
}

TEST(Textures, Ktx1RowsOfThreeHalvesArePaddedToFourBytes) {
  const Texture t = makeTexture(3, 2, 1, 1, [](int, int, int x, int y) { return Rgba(x, y, 2, 1); });
  const std::string bytes = encodeTexture(t, TextureContainer::Ktx1, TexelFormat::Rgb16Float).bytes;
  const std::uint32_t kvd = u32At(bytes, 60);
  EXPECT_EQ(u32At(bytes, 64 + kvd), 2u * 20);  // rows of 18 bytes padded to 20
  const Texture back = decodeTexture(bytes, "t");
  EXPECT_EQ(back.levels[0][0].at(2, 1)[0], 2.0f);
  EXPECT_EQ(back.levels[0][0].at(2, 1)[1], 1.0f);
}

// ---- malformed files -----------------------------------------------------------------------------

void expectRefused(const std::string& bytes, const std::string& label, const std::string& fragment) {
  try {
    (void)decodeTexture(bytes, label);
    ADD_FAILURE() << "accepted; expected an error with '" << fragment << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput) << e.what();
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(label, 0), 0u) << what;  // the file first
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

std::string withU32(std::string bytes, std::size_t offset, std::uint32_t value) {
  if (offset + 4 > bytes.size()) throw std::out_of_range("withU32: past the file's end");
  std::memcpy(bytes.data() + offset, &value, 4);
  return bytes;
}
std::string withU64(std::string bytes, std::size_t offset, std::uint64_t value) {
  if (offset + 8 > bytes.size()) throw std::out_of_range("withU64: past the file's end");
  std::memcpy(bytes.data() + offset, &value, 8);
  return bytes;
}

TEST(Textures, TruncatedAtEveryByteIsRefusedNamingTheFile) {
  Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int x, int y) { return Rgba(k, f, x, y); });
  cube.metadata = {{"parameterization", "cube"}};
  for (const TextureContainer container : kContainers) {
    const std::string bytes = encodeTexture(cube, container, TexelFormat::Rgba16Float).bytes;
    const std::string label = "cut." + std::string(toString(container));
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      try {
        (void)decodeTexture(std::string_view(bytes).substr(0, n), label);
        ADD_FAILURE() << toString(container) << " truncated to " << n << " of " << bytes.size() << " bytes: accepted";
      } catch (const Error& e) {
        ASSERT_EQ(std::string(e.what()).rfind(label + ": ", 0), 0u) << e.what();
      }
    }
  }
}

// A 64 KiB memory budget: a file that claims more texels than it holds must be refused for its
// size (InvalidInput), not found out by the budget (Resource) or by the allocator.
class TinyMemoryBudget {
 public:
  TinyMemoryBudget() { ::setenv("BRDFBAKE_MEMORY_LIMIT", "64K", 1); }
  ~TinyMemoryBudget() { ::unsetenv("BRDFBAKE_MEMORY_LIMIT"); }
};

TEST(Textures, Ktx2ThatLiesAboutItsSizesIsRefused) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int x, int y) { return Rgba(k, f, x, y); });
  const std::string good = encodeTexture(cube, TextureContainer::Ktx2, TexelFormat::Rgba16Float).bytes;
  const TinyMemoryBudget budget;
  expectRefused(withU32(good, 12, 37), "a.ktx2", "unsupported vkFormat 37");
  expectRefused(withU32(good, 16, 4), "a.ktx2", "typeSize");
  expectRefused(withU32(withU32(good, 20, 0x7FFFFFFF), 24, 0x7FFFFFFF), "a.ktx2", "outside 1 to 65536");
  expectRefused(withU32(withU32(good, 20, 65536), 24, 65536), "a.ktx2", "level 0 has");  // 2^32 texels claimed
  expectRefused(withU32(good, 20, 5), "a.ktx2", "square");
  expectRefused(withU32(good, 28, 2), "a.ktx2", "3-D");
  expectRefused(withU32(good, 32, 2), "a.ktx2", "array");
  expectRefused(withU32(good, 36, 3), "a.ktx2", "face count 3");
  expectRefused(withU32(good, 40, 4), "a.ktx2", "more than a 4 x 4 texture allows");
  expectRefused(withU32(good, 40, 1u << 30), "a.ktx2", "mip levels");
  expectRefused(withU32(good, 44, 2), "a.ktx2", "supercompressed");
  expectRefused(withU32(good, 52, 0xFFFFFF00u), "a.ktx2", "data format descriptor");
  expectRefused(withU32(good, 152, 12), "a.ktx2", "dfdTotalSize");
  expectRefused(withU32(good, 60, 0x7FFFFFFF), "a.ktx2", "key/value data");
  expectRefused(withU64(good, 72, 16), "a.ktx2", "global data");
  expectRefused(withU64(good, 80, ~0ull - 4), "a.ktx2", "level 0");        // offset at the end of 2^64
  expectRefused(withU64(good, 80, good.size() - 8), "a.ktx2", "level 0");  // runs past the end
  expectRefused(withU64(good, 88, 1ull << 62), "a.ktx2", "level 0 has");
  expectRefused(withU64(good, 96 + 24, 7), "a.ktx2", "level 1 has");  // uncompressed length lies
  expectRefused(withU64(good, 80, 0), "a.ktx2", "overlaps the header");
  // A key/value entry longer than the key/value data, and a malformed metadata value.
  const std::uint32_t kvd = u32At(good, 56);
  expectRefused(withU32(good, kvd, 5000), "a.ktx2", "key/value entry 0");
}

TEST(Textures, KeyValueDataIsChecked) {
  Texture t = makeTexture(2, 2, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  t.metadata = {{"a", 1}};
  const std::string good = encodeTexture(t, TextureContainer::Ktx2, TexelFormat::Rgba32Float).bytes;
  std::string broken = good;
  const std::size_t at = broken.find("{\"a\":1}");
  ASSERT_NE(at, std::string::npos);
  broken[at + 1] = '!';
  expectRefused(broken, "m.ktx2", "brdfbake.metadata");
  std::string array = good;
  array.replace(at, 7, "[1,2,3]");
  expectRefused(array, "m.ktx2", "not a JSON object");
}

TEST(Textures, DdsAndKtx1ThatLieAreRefused) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int x, int y) { return Rgba(k, f, x, y); });
  const std::string dds = encodeTexture(cube, TextureContainer::Dds, TexelFormat::Rgba16Float).bytes;
  const TinyMemoryBudget budget;
  expectRefused(withU32(dds, 28, 9), "a.dds", "more than");
  expectRefused(withU32(withU32(dds, 12, 60000), 16, 60000), "a.dds", "truncated");
  expectRefused(withU32(dds, 128, 28), "a.dds", "unsupported DXGI format 28");
  expectRefused(withU32(dds, 140, 2), "a.dds", "arrays");
  expectRefused(withU32(dds, 132, 4), "a.dds", "dimension");
  expectRefused(withU32(dds, 4, 100), "a.dds", "header sizes");
  expectRefused(withU32(dds, 80, 0x40), "a.dds", "RGB masks");
  expectRefused(withU32(dds, 84, 0x31545844), "a.dds", "'DXT1'");
  expectRefused(withU32(withU32(dds, 84, 113), 112, 0x200 | 0x400), "a.dds", "six faces");
  const std::string ktx = encodeTexture(cube, TextureContainer::Ktx1, TexelFormat::Rgba16Float).bytes;
  expectRefused(withU32(ktx, 12, 0x01020304u), "a.ktx", "big-endian");
  expectRefused(withU32(ktx, 28, 0x8058), "a.ktx", "unsupported glInternalFormat");
  expectRefused(withU32(ktx, 16, 0x1406), "a.ktx", "do not match GL_RGBA16F");
  expectRefused(withU32(ktx, 48, 2), "a.ktx", "array");
  expectRefused(withU32(ktx, 60, 0x7FFFFFFF), "a.ktx", "key/value data");
  expectRefused(withU32(ktx, 64 + u32At(ktx, 60), 7), "a.ktx", "imageSize is 7");
  expectRefused(withU32(withU32(ktx, 36, 65536), 40, 65536), "a.ktx", "imageSize");
  expectRefused("not a texture at all", "a.ktx2", "not a KTX2, KTX or DDS file");
}

TEST(Textures, NonFiniteTexelsAreRefusedNamingLevelFaceAndTexel) {
  const Texture cube = makeTexture(4, 4, 6, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  const std::string good = encodeTexture(cube, TextureContainer::Ktx2, TexelFormat::Rgba16Float).bytes;
  // Face +Y (2), texel (1, 2), green: byte 2 x 128 + (2 x 4 + 1) x 8 + 2 of level 0.
  const std::size_t at = static_cast<std::size_t>(u64At(good, 80)) + 2 * 128 + 9 * 8 + 2;
  std::string inf = good, nan = good;
  inf[at] = 0x00, inf[at + 1] = 0x7C;
  nan[at] = 0x00, nan[at + 1] = 0x7E;
  expectRefused(inf, "i.ktx2", "level 0 face +Y: texel (1, 2) is infinite");
  expectRefused(nan, "n.ktx2", "level 0 face +Y: texel (1, 2) is NaN");
  const Texture flat = makeTexture(2, 1, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  std::string packed = encodeTexture(flat, TextureContainer::Dds, TexelFormat::B10g11r11).bytes;
  packed = withU32(packed, 148 + 4, 31u << 6);  // red exponent 31: infinity
  expectRefused(packed, "p.dds", "texel (1, 0) is infinite");
}

TEST(Textures, Ktx2OrientationRuIsReadBottomUpAndRefusedForCubes) {
  const Texture flat = makeTexture(2, 2, 1, 1, [](int, int, int, int y) { return Rgba(y, 0, 0, 1); });
  std::string bytes = encodeTexture(flat, TextureContainer::Ktx2, TexelFormat::Rgba32Float).bytes;
  const std::size_t at = bytes.find(std::string("KTXorientation\0rd", 17));
  ASSERT_NE(at, std::string::npos);
  bytes[at + 16] = 'u';
  const Texture back = decodeTexture(bytes, "u.ktx2");
  EXPECT_EQ(back.levels[0][0].at(0, 0)[0], 1.0f);  // the file's first row is the bottom one
  EXPECT_EQ(back.levels[0][0].at(0, 1)[0], 0.0f);
  const Texture cube = makeTexture(2, 2, 6, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  std::string cubeBytes = encodeTexture(cube, TextureContainer::Ktx2, TexelFormat::Rgba32Float).bytes;
  cubeBytes[cubeBytes.find(std::string("KTXorientation\0rd", 17)) + 16] = 'u';
  expectRefused(cubeBytes, "c.ktx2", "KTXorientation 'ru' is not supported");
}

TEST(Textures, LevelBeyondTheFileIsRefused) {
  const Texture t = makeTexture(4, 4, 1, 3, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  const std::string bytes = encodeTexture(t, TextureContainer::Ktx2, TexelFormat::Rgba16Float).bytes;
  EXPECT_EQ(decodeTexture(bytes, "t", 2).levels[0][0].width(), 1);
  try {
    (void)decodeTexture(bytes, "t.ktx2", 3);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.ktx2: has 3 MIP levels, no level 3"), std::string::npos) << e.what();
  }
}

TEST(Textures, InvalidTexturesAreNotWritten) {
  test::TempDir dir;
  Texture t = makeTexture(4, 4, 1, 3, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  t.levels[1][0].set(0, 0, Rgba(NAN, 0, 0, 1));
  EXPECT_THROW(writeTexture(t, dir / "nan.ktx2"), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "nan.ktx2"));
  Texture wrong = makeTexture(4, 4, 1, 2, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  wrong.levels[1][0] = Image(3, 2);
  EXPECT_THROW(writeTexture(wrong, dir / "sizes.dds"), Error);
  EXPECT_THROW(
      writeTexture(makeTexture(4, 4, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); }), dir / "x.png"), Error);
  WriteOptions rgb16;
  rgb16.texelFormat = TexelFormat::Rgb16Float;
  EXPECT_THROW(
      writeTexture(makeTexture(4, 4, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); }), dir / "x.dds", rgb16),
      Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// A DDS file without the DX10 header, written here from Microsoft's DDS_HEADER and DDS_PIXELFORMAT:
// the four-character code 113 is D3DFMT_A16B16G16R16F (R, G, B, A halves in that order in memory),
// 116 D3DFMT_A32B32G32R32F (R, G, B, A floats).
std::string legacyDds(std::uint32_t fourCC, std::uint32_t width, std::uint32_t height, const std::string& texels) {
  std::string out("DDS ");
  const auto put = [&out](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put(124);                       // dwSize
  put(0x1 | 0x2 | 0x4 | 0x1000);  // DDSD_CAPS | HEIGHT | WIDTH | PIXELFORMAT
  put(height);
  put(width);
  put(0);                               // dwPitchOrLinearSize
  put(0);                               // dwDepth
  put(0);                               // dwMipMapCount: 0 means one level
  for (int i = 0; i < 11; ++i) put(0);  // dwReserved1
  put(32);                              // ddspf.dwSize
  put(0x4);                             // DDPF_FOURCC
  put(fourCC);
  for (int i = 0; i < 5; ++i) put(0);  // bit count and masks
  put(0x1000);                         // DDSCAPS_TEXTURE
  for (int i = 0; i < 4; ++i) put(0);  // dwCaps2, dwCaps3, dwCaps4, dwReserved2
  return out + texels;
}

TEST(Textures, LegacyDdsFourCcFilesAreReadAsTheirFormats) {
  // Two texels (1, 2, 0.5, 1) and (0.25, 4, 0, 1): halves 0x3C00 0x4000 0x3800 0x3C00, 0x3400 0x4400 0 0x3C00.
  const std::uint16_t halves[8] = {0x3C00, 0x4000, 0x3800, 0x3C00, 0x3400, 0x4400, 0x0000, 0x3C00};
  const float floats[8] = {1.0f, 2.0f, 0.5f, 1.0f, 0.25f, 4.0f, 0.0f, 1.0f};
  const std::string files[2] = {
      legacyDds(113, 2, 1, std::string(reinterpret_cast<const char*>(halves), sizeof halves)),
      legacyDds(116, 2, 1, std::string(reinterpret_cast<const char*>(floats), sizeof floats))};
  for (const std::string& bytes : files) {
    const Texture t = decodeTexture(bytes, "legacy.dds");
    ASSERT_EQ(t.levelCount(), 1);
    ASSERT_EQ(t.faceCount(), 1);
    const Image& image = t.levels[0][0];
    ASSERT_EQ(image.width(), 2);
    ASSERT_EQ(image.height(), 1);
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 4; ++c) EXPECT_EQ(image.at(x, 0)[c], floats[4 * x + c]) << x << " " << c;
  }
}

// One byte short: the parser refuses it for its size (InvalidInput, "truncated"), whichever
// container, before a row is decoded.
TEST(Textures, AFileOneByteShortIsRefusedAsTruncated) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int x, int y) { return Rgba(k, f, x, y); });
  for (const TextureContainer container : kContainers) {
    const std::string bytes = encodeTexture(cube, container, TexelFormat::Rgba16Float).bytes;
    expectRefused(bytes.substr(0, bytes.size() - 1), "short.tex", "truncated");
  }
}

// A cube's level holds six faces: 4 x 4 half-float RGBA faces are 128 bytes, so level 0 is 768; a
// level index claiming one face's 128 bytes is refused (KTX2 specification, levelIndex).
TEST(Textures, Ktx2CubeLevelLengthMustHoldAllSixFaces) {
  const Texture cube = makeTexture(4, 4, 6, 3, [](int k, int f, int x, int y) { return Rgba(k, f, x, y); });
  const std::string good = encodeTexture(cube, TextureContainer::Ktx2, TexelFormat::Rgba16Float).bytes;
  ASSERT_EQ(u64At(good, 88), 6u * 128u);  // level 0: byteLength
  expectRefused(withU64(withU64(good, 88, 128), 96, 128), "a.ktx2", "level 0");
}

// A key/value entry's length one to four bytes more than the key/value data has left is refused.
TEST(Textures, KeyValueEntryRunningPastTheKeyValueDataIsRefused) {
  Texture t = makeTexture(2, 2, 1, 1, [](int, int, int, int) { return Rgba(1, 1, 1, 1); });
  t.metadata = {{"a", 1}};
  const std::string good = encodeTexture(t, TextureContainer::Ktx2, TexelFormat::Rgba32Float).bytes;
  const std::uint32_t kvd = u32At(good, 56), left = u32At(good, 60) - 4;
  for (std::uint32_t extra = 1; extra <= 4; ++extra) {
    expectRefused(withU32(good, kvd, left + extra), "a.ktx2", "key/value entry 0: length");
  }
}

}  // namespace
}  // namespace brdfbake
