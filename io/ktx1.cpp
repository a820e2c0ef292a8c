// KTX 1.1 (Khronos, "KTX File Format Specification", 2018): OpenGL float formats, 2-D textures and
// cube maps with mip levels, little-endian.
#include <brdfbake/core/error.hpp>

#include <cstring>

#include "texture_codecs.hpp"

namespace brdfbake::texture_detail {
namespace {

constexpr unsigned char kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '1', '1', 0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::uint64_t kHeaderBytes = 64;
constexpr std::uint32_t kEndianness = 0x04030201u;

// OpenGL enums (glcorearb.h) of each format: glType, glTypeSize, glFormat (= base internal format),
// glInternalFormat.
struct GlFormatRow {
  TexelFormat format;
  std::uint32_t type, typeSize, baseFormat, internalFormat;
  const char* name;
};
constexpr std::uint32_t kGlRgb = 0x1907, kGlRgba = 0x1908, kGlHalfFloat = 0x140B, kGlFloat = 0x1406;
constexpr GlFormatRow kGlFormats[] = {
    {TexelFormat::Rgba16Float, kGlHalfFloat, 2, kGlRgba, 0x881A, "GL_RGBA16F"},
    {TexelFormat::Rgba32Float, kGlFloat, 4, kGlRgba, 0x8814, "GL_RGBA32F"},
    {TexelFormat::Rgb16Float, kGlHalfFloat, 2, kGlRgb, 0x881B, "GL_RGB16F"},
    {TexelFormat::Rgb32Float, kGlFloat, 4, kGlRgb, 0x8815, "GL_RGB32F"},
    {TexelFormat::Rgb9e5, 0x8C3E /* GL_UNSIGNED_INT_5_9_9_9_REV */, 4, kGlRgb, 0x8C3D, "GL_RGB9_E5"},
    {TexelFormat::B10g11r11, 0x8C3B /* GL_UNSIGNED_INT_10F_11F_11F_REV */, 4, kGlRgb, 0x8C3A, "GL_R11F_G11F_B10F"},
};

const GlFormatRow& glRow(TexelFormat format) {
  for (const auto& r : kGlFormats)
    if (r.format == format) return r;
  throw Error(Error::Kind::InvalidArgument, "KTX1: no OpenGL format for this texel format");
}

// Rows of KTX1 images are padded to GL_UNPACK_ALIGNMENT 4.
std::uint64_t rowPitch(std::uint64_t width, std::uint64_t texel) { return (width * texel + 3) / 4 * 4; }

}  // namespace

std::string encodeKtx1(const Texture& texture, TexelFormat format, const KeyValues& keyValues, EncodingTally& tally) {
  const GlFormatRow& gl = glRow(format);
  std::string kvd;
  for (const auto& [key, value] : keyValues) {
    putU32(kvd, static_cast<std::uint32_t>(key.size() + 1 + value.size()));
    kvd += key;
    kvd.push_back('\0');
    kvd += value;
    padTo(kvd, 4);  // valuePadding
  }
  std::string out(reinterpret_cast<const char*>(kIdentifier), sizeof kIdentifier);
  for (const std::uint32_t v :
       {kEndianness, gl.type, gl.typeSize, gl.baseFormat, gl.internalFormat, gl.baseFormat,
        static_cast<std::uint32_t>(texture.width()), static_cast<std::uint32_t>(texture.height()), 0u /* depth */,
        0u /* array elements */, static_cast<std::uint32_t>(texture.faceCount()),
        static_cast<std::uint32_t>(texture.levelCount()), static_cast<std::uint32_t>(kvd.size())}) {
    putU32(out, v);
  }
  out += kvd;
  const std::uint64_t texel = static_cast<std::uint64_t>(bytesPerTexel(format));
  for (const auto& level : texture.levels) {
    // imageSize: one face's bytes for a (non-array) cube map, else the level's.
    const std::uint64_t faceBytes = rowPitch(level[0].width(), texel) * level[0].height();
    putU32(out, static_cast<std::uint32_t>(texture.isCube() ? faceBytes : faceBytes * level.size()));
    // Faces are whole rows of 4-byte multiples: no cubePadding or mipPadding is ever needed.
    appendLevel(out, level, format, 4, tally);
  }
  return out;
}

ParsedTexture parseKtx1(std::string_view bytes, const std::string& label) {
  const ByteReader in(bytes, label);
  in.requireRange(0, kHeaderBytes, "the KTX header");
  if (std::memcmp(bytes.data(), kIdentifier, sizeof kIdentifier) != 0) in.fail("not a KTX 1 file (bad identifier)");
  const std::uint32_t endianness = in.u32(12, "endianness");
  if (endianness != kEndianness) {
    in.fail(endianness == 0x01020304u ? "big-endian KTX files are not supported"
                                      : "bad endianness field " + std::to_string(endianness));
  }
  const std::uint32_t type = in.u32(16, "glType"), typeSize = in.u32(20, "glTypeSize");
  const std::uint32_t glFormat = in.u32(24, "glFormat"), internalFormat = in.u32(28, "glInternalFormat");
  const GlFormatRow* gl = nullptr;
  for (const auto& r : kGlFormats)
    if (r.internalFormat == internalFormat) gl = &r;
  if (!gl) {
    in.fail("unsupported glInternalFormat " + std::to_string(internalFormat) + (type == 0 ? " (compressed)" : "") +
            " (brdfbake reads GL_RGBA16F, GL_RGBA32F, GL_RGB16F, GL_RGB32F, GL_RGB9_E5 and GL_R11F_G11F_B10F)");
  }
  if (type != gl->type || typeSize != gl->typeSize || glFormat != gl->baseFormat) {
    in.fail(std::string("glType, glTypeSize or glFormat do not match ") + gl->name);
  }
  const std::uint64_t width = in.u32(36, "pixelWidth"), height = std::max<std::uint32_t>(1, in.u32(40, "pixelHeight"));
  const std::uint32_t depth = in.u32(44, "pixelDepth"), elements = in.u32(48, "numberOfArrayElements");
  const std::uint64_t faces = in.u32(52, "numberOfFaces");
  const std::uint64_t levels = std::max<std::uint32_t>(1, in.u32(56, "numberOfMipmapLevels"));
  const std::uint64_t kvdLength = in.u32(60, "bytesOfKeyValueData");
  if (depth != 0) in.fail("3-D textures are not supported (pixelDepth " + std::to_string(depth) + ")");
  if (elements != 0)
    in.fail("array textures are not supported (numberOfArrayElements " + std::to_string(elements) + ")");
  checkShape(in, width, height, faces, levels);

  ParsedTexture parsed;
  parsed.header.container = TextureContainer::Ktx1;
  parsed.header.format = gl->format;
  parsed.header.width = static_cast<int>(width);
  parsed.header.height = static_cast<int>(height);
  parsed.header.faces = static_cast<int>(faces);
  parsed.header.levels = static_cast<int>(levels);
  in.requireRange(kHeaderBytes, kvdLength, "the key/value data");
  if (kvdLength > 0) applyKeyValues(parsed, parseKeyValues(in, kHeaderBytes, kvdLength), in, true);

  const std::uint64_t texel = static_cast<std::uint64_t>(bytesPerTexel(gl->format));
  std::uint64_t offset = kHeaderBytes + kvdLength;
  for (std::uint64_t k = 0; k < levels; ++k) {
    const std::string name = "level " + std::to_string(k);
    const std::uint64_t w = levelSize(width, static_cast<int>(k)), h = levelSize(height, static_cast<int>(k));
    const std::uint64_t pitch = rowPitch(w, texel), faceBytes = pitch * h;
    const std::uint64_t imageSize = in.u32(offset, name + " imageSize");
    const std::uint64_t expected = faces == 6 ? faceBytes : faceBytes * faces;
    if (imageSize != expected) {
      in.fail(name + " imageSize is " + std::to_string(imageSize) + " but " + std::to_string(w) + " x " +
              std::to_string(h) + (faces == 6 ? " cube faces need " : " texels need ") + std::to_string(expected));
    }
    offset += 4;
    parsed.images.emplace_back();
    for (std::uint64_t f = 0; f < faces; ++f) {
      in.requireRange(offset, faceBytes, name + (faces == 6 ? " face " + std::to_string(f) : std::string()));
      parsed.images.back().push_back({offset, pitch});
      offset += (faceBytes + 3) / 4 * 4;  // cubePadding
    }
    offset = (offset + 3) / 4 * 4;  // mipPadding
  }
  return parsed;
}

}  // namespace brdfbake::texture_detail
