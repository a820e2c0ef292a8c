// DirectDraw Surface files (Microsoft, "Programming Guide for DDS": DDS_HEADER and DDS_HEADER_DXT10):
// uncompressed float DXGI formats, 2-D textures and cube maps with mip levels. Reads also the
// legacy D3DFMT_A16B16G16R16F / A32B32G32R32F four-character codes.
#include <brdfbake/core/error.hpp>

#include <cstring>

#include "texture_codecs.hpp"

namespace brdfbake::texture_detail {
namespace {

constexpr std::uint32_t kMagic = 0x20534444u;  // "DDS "
constexpr std::uint64_t kHeaderBytes = 4 + 124, kDx10Bytes = 20;
// DDS_HEADER.dwFlags
constexpr std::uint32_t kCaps = 0x1, kHeight = 0x2, kWidth = 0x4, kPitch = 0x8, kPixelFormat = 0x1000,
                        kMipMapCount = 0x20000, kDepth = 0x800000;
// dwCaps, dwCaps2
constexpr std::uint32_t kCapsComplex = 0x8, kCapsTexture = 0x1000, kCapsMipMap = 0x400000;
constexpr std::uint32_t kCaps2Cubemap = 0x200, kCaps2AllFaces = 0xFC00, kCaps2Volume = 0x200000;
// DDS_PIXELFORMAT.dwFlags, DDS_HEADER_DXT10
constexpr std::uint32_t kPixelFourCC = 0x4;
constexpr std::uint32_t kFourCCDx10 = 0x30315844u;  // "DX10"
constexpr std::uint32_t kDimensionTexture1D = 2, kDimensionTexture2D = 3, kMiscTextureCube = 0x4;
constexpr std::uint32_t kAlphaModeUnknown = 0, kAlphaModeStraight = 1;

// DXGI_FORMAT values (dxgiformat.h).
struct DxgiRow {
  TexelFormat format;
  std::uint32_t dxgi;
};
constexpr DxgiRow kDxgiFormats[] = {
    {TexelFormat::Rgba16Float, 10},  // DXGI_FORMAT_R16G16B16A16_FLOAT
    {TexelFormat::Rgba32Float, 2},   // DXGI_FORMAT_R32G32B32A32_FLOAT
    {TexelFormat::Rgb32Float, 6},    // DXGI_FORMAT_R32G32B32_FLOAT
    {TexelFormat::Rgb9e5, 67},       // DXGI_FORMAT_R9G9B9E5_SHAREDEXP (same bits as E5B9G9R9)
    {TexelFormat::B10g11r11, 26},    // DXGI_FORMAT_R11G11B10_FLOAT (same bits as B10G11R11)
};

std::uint32_t dxgiOf(TexelFormat format) {
  for (const auto& r : kDxgiFormats)
    if (r.format == format) return r.dxgi;
  throw Error(Error::Kind::InvalidArgument, "DDS: no DXGI format for " + std::string(toString(format)));
}

}  // namespace

std::string encodeDds(const Texture& texture, TexelFormat format, EncodingTally& tally) {
  const std::uint32_t dxgi = dxgiOf(format);
  const std::uint32_t levels = static_cast<std::uint32_t>(texture.levelCount());
  const std::uint32_t width = static_cast<std::uint32_t>(texture.width());
  const std::uint32_t height = static_cast<std::uint32_t>(texture.height());
  std::string out;
  putU32(out, kMagic);
  putU32(out, 124);  // dwSize
  putU32(out, kCaps | kHeight | kWidth | kPitch | kPixelFormat | kMipMapCount);
  putU32(out, height);
  putU32(out, width);
  putU32(out, width * static_cast<std::uint32_t>(bytesPerTexel(format)));  // dwPitchOrLinearSize: row bytes
  putU32(out, 0);                                                          // dwDepth
  putU32(out, levels);                                                     // dwMipMapCount
  for (int i = 0; i < 11; ++i) putU32(out, 0);                             // dwReserved1
  putU32(out, 32);                                                         // DDS_PIXELFORMAT: dwSize
  putU32(out, kPixelFourCC);
  putU32(out, kFourCCDx10);
  for (int i = 0; i < 5; ++i) putU32(out, 0);  // dwRGBBitCount and the four masks
  putU32(out, kCapsTexture | (levels > 1 ? kCapsMipMap | kCapsComplex : 0) | (texture.isCube() ? kCapsComplex : 0));
  putU32(out, texture.isCube() ? kCaps2Cubemap | kCaps2AllFaces : 0);
  putU32(out, 0);  // dwCaps3
  putU32(out, 0);  // dwCaps4
  putU32(out, 0);  // dwReserved2
  putU32(out, dxgi);
  putU32(out, kDimensionTexture2D);
  putU32(out, texture.isCube() ? kMiscTextureCube : 0);
  putU32(out, 1);  // arraySize: one texture (one cube)
  putU32(out, hasAlpha(format) ? kAlphaModeStraight : kAlphaModeUnknown);
  // Faces outer, levels inner.
  for (int f = 0; f < texture.faceCount(); ++f) {
    for (const auto& level : texture.levels) appendImage(out, level[static_cast<std::size_t>(f)], format, 1, tally);
  }
  return out;
}

ParsedTexture parseDds(std::string_view bytes, const std::string& label) {
  const ByteReader in(bytes, label);
  in.requireRange(0, kHeaderBytes, "the DDS header");
  if (in.u32(0, "magic") != kMagic) in.fail("not a DDS file (bad magic)");
  if (in.u32(4, "dwSize") != 124 || in.u32(76, "ddspf.dwSize") != 32) in.fail("bad DDS header sizes");
  const std::uint32_t flags = in.u32(8, "dwFlags");
  const std::uint64_t height = in.u32(12, "dwHeight"), width = in.u32(16, "dwWidth");
  const std::uint32_t mipMapCount = in.u32(28, "dwMipMapCount");
  const std::uint32_t pixelFlags = in.u32(80, "ddspf.dwFlags"), fourCC = in.u32(84, "ddspf.dwFourCC");
  const std::uint32_t caps2 = in.u32(112, "dwCaps2");
  if ((flags & kDepth) || (caps2 & kCaps2Volume)) in.fail("volume (3-D) textures are not supported");
  if (!(pixelFlags & kPixelFourCC)) {
    in.fail("unsupported pixel format (RGB masks, not a four-character code); brdfbake reads float DDS files");
  }
  std::optional<TexelFormat> format;
  std::uint64_t dataOffset = kHeaderBytes, faces = 1;
  if (fourCC == kFourCCDx10) {
    in.requireRange(kHeaderBytes, kDx10Bytes, "the DX10 header");
    const std::uint32_t dxgi = in.u32(128, "dxgiFormat"), dimension = in.u32(132, "resourceDimension");
    const std::uint32_t misc = in.u32(136, "miscFlag"), arraySize = in.u32(140, "arraySize");
    for (const auto& r : kDxgiFormats)
      if (r.dxgi == dxgi) format = r.format;
    if (!format) {
      in.fail("unsupported DXGI format " + std::to_string(dxgi) +
              " (brdfbake reads R16G16B16A16_FLOAT, R32G32B32A32_FLOAT, R32G32B32_FLOAT, R9G9B9E5_SHAREDEXP and "
              "R11G11B10_FLOAT)");
    }
    if (dimension != kDimensionTexture2D && dimension != kDimensionTexture1D) {
      in.fail("resource dimension " + std::to_string(dimension) +
              " is not supported (2-D textures and cube maps only)");
    }
    if (arraySize != 1) in.fail("texture arrays are not supported (arraySize " + std::to_string(arraySize) + ")");
    if (misc & kMiscTextureCube) faces = 6;
    dataOffset += kDx10Bytes;
  } else {
    // D3DFMT_A16B16G16R16F (113) and D3DFMT_A32B32G32R32F (116): the same bytes as the DXGI RGBA formats.
    if (fourCC == 113) format = TexelFormat::Rgba16Float;
    if (fourCC == 116) format = TexelFormat::Rgba32Float;
    if (!format) {
      std::string code;
      for (int i = 0; i < 4; ++i) {
        const char c = static_cast<char>((fourCC >> (8 * i)) & 0xFF);
        code += (c >= 32 && c < 127) ? c : '?';
      }
      in.fail("unsupported four-character code '" + code + "' (" + std::to_string(fourCC) +
              "); brdfbake reads the DX10 header's float formats and D3DFMT_A16B16G16R16F / A32B32G32R32F");
    }
    if (caps2 & kCaps2Cubemap) {
      if ((caps2 & kCaps2AllFaces) != kCaps2AllFaces) in.fail("cube maps without all six faces are not supported");
      faces = 6;
    }
  }
  const std::uint64_t levels = std::max<std::uint32_t>(1, mipMapCount);
  checkShape(in, width, std::max<std::uint64_t>(1, height), faces, levels);

  ParsedTexture parsed;
  parsed.header.container = TextureContainer::Dds;
  parsed.header.format = *format;
  parsed.header.width = static_cast<int>(width);
  parsed.header.height = static_cast<int>(std::max<std::uint64_t>(1, height));
  parsed.header.faces = static_cast<int>(faces);
  parsed.header.levels = static_cast<int>(levels);
  const std::uint64_t texel = static_cast<std::uint64_t>(bytesPerTexel(*format));
  parsed.images.assign(levels, std::vector<ImageSpan>(faces));
  std::uint64_t offset = dataOffset;
  for (std::uint64_t f = 0; f < faces; ++f) {
    for (std::uint64_t k = 0; k < levels; ++k) {
      const std::uint64_t w = levelSize(width, static_cast<int>(k));
      const std::uint64_t h = levelSize(parsed.header.height, static_cast<int>(k));
      in.requireRange(offset, w * h * texel,
                      (faces == 6 ? "face " + std::to_string(f) + " " : std::string()) + "level " + std::to_string(k));
      parsed.images[k][f] = {offset, w * texel};
      offset += w * h * texel;
    }
  }
  return parsed;
}

}  // namespace brdfbake::texture_detail
