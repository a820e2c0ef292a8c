// KTX 2.0 (Khronos, "KTX File Format Specification" version 2): uncompressed float formats, 2-D
// textures and cube maps with mip levels, no supercompression.
#include <brdfbake/core/error.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <numeric>

#include "texture_codecs.hpp"

namespace brdfbake::texture_detail {
namespace {

constexpr unsigned char kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::uint64_t kHeaderBytes = 80;  // identifier, 9 UInt32, 4 UInt32 + 2 UInt64 of index
constexpr std::uint64_t kLevelEntryBytes = 24;

// VkFormat values (Vulkan 1.0 core) and typeSize of each format brdfbake writes or reads.
struct VkFormatRow {
  TexelFormat format;
  std::uint32_t vkFormat;
  std::uint32_t typeSize;
  const char* name;
};
constexpr VkFormatRow kVkFormats[] = {
    {TexelFormat::Rgba16Float, 97, 2, "VK_FORMAT_R16G16B16A16_SFLOAT"},
    {TexelFormat::Rgba32Float, 109, 4, "VK_FORMAT_R32G32B32A32_SFLOAT"},
    {TexelFormat::Rgb16Float, 90, 2, "VK_FORMAT_R16G16B16_SFLOAT"},
    {TexelFormat::Rgb32Float, 106, 4, "VK_FORMAT_R32G32B32_SFLOAT"},
    {TexelFormat::Rgb9e5, 123, 4, "VK_FORMAT_E5B9G9R9_UFLOAT_PACK32"},
    {TexelFormat::B10g11r11, 122, 4, "VK_FORMAT_B10G11R11_UFLOAT_PACK32"},
};

const VkFormatRow& vkRow(TexelFormat format) {
  for (const auto& r : kVkFormats)
    if (r.format == format) return r;
  throw Error(Error::Kind::InvalidArgument, "KTX2: no VkFormat for this texel format");
}

// Khronos Data Format Specification 1.3, section 5 (basic descriptor block) and the KTX-Software
// descriptors of these formats: colour model RGBSDA (1), primaries BT.709 (1), transfer linear
// (1), straight alpha, 1x1x1x1 texel blocks, one plane of bytesPerTexel bytes.
constexpr std::uint32_t kChannelAlpha = 15;
constexpr std::uint32_t kQualifierFloat = 0x80, kQualifierSigned = 0x40, kQualifierExponent = 0x20;
constexpr std::uint32_t kFloatOne = 0x3F800000u, kFloatMinusOne = 0xBF800000u;

struct Sample {
  std::uint32_t bitOffset, bitLength, channel, lower, upper;
};

std::vector<Sample> samplesOf(TexelFormat format) {
  std::vector<Sample> samples;
  switch (format) {
    case TexelFormat::Rgba16Float:
    case TexelFormat::Rgba32Float:
    case TexelFormat::Rgb16Float:
    case TexelFormat::Rgb32Float: {
      // Signed floats: sampleLower -1.0f, sampleUpper 1.0f.
      const std::uint32_t bits = (format == TexelFormat::Rgba16Float || format == TexelFormat::Rgb16Float) ? 16 : 32;
      const int channels = hasAlpha(format) ? 4 : 3;
      for (int c = 0; c < channels; ++c) {
        const std::uint32_t id = c == 3 ? kChannelAlpha : static_cast<std::uint32_t>(c);
        samples.push_back({bits * c, bits - 1, id | kQualifierFloat | kQualifierSigned, kFloatMinusOne, kFloatOne});
      }
      break;
    }
    case TexelFormat::Rgb9e5:
      // Per channel a 9-bit mantissa (upper 8448) and the shared exponent (bits 27-31, bias 15, max 31).
      for (std::uint32_t c = 0; c < 3; ++c) {
        samples.push_back({9 * c, 8, c, 0, 8448});
        samples.push_back({27, 4, c | kQualifierExponent, 15, 31});
      }
      break;
    case TexelFormat::B10g11r11:
      // Unsigned floats: sampleLower 0.0f, sampleUpper 1.0f.
      samples.push_back({0, 10, 0 | kQualifierFloat, 0, kFloatOne});
      samples.push_back({11, 10, 1 | kQualifierFloat, 0, kFloatOne});
      samples.push_back({22, 9, 2 | kQualifierFloat, 0, kFloatOne});
      break;
  }
  return samples;
}

// dfdTotalSize, then one basic descriptor block.
std::string dataFormatDescriptor(TexelFormat format) {
  const std::vector<Sample> samples = samplesOf(format);
  const std::uint32_t blockSize = 24 + 16 * static_cast<std::uint32_t>(samples.size());
  std::string out;
  putU32(out, 4 + blockSize);
  putU32(out, 0);                            // vendorId 0 (Khronos), descriptorType 0 (basic)
  putU32(out, 2u | (blockSize << 16));       // versionNumber 2 (KDFS 1.3), descriptorBlockSize
  putU32(out, 1u | (1u << 8) | (1u << 16));  // colorModel RGBSDA, primaries BT709, transfer linear, flags 0
  putU32(out, 0);                            // texelBlockDimension 1x1x1x1 (stored minus 1)
  putU32(out, static_cast<std::uint32_t>(bytesPerTexel(format)));  // bytesPlane0; planes 1-3 zero
  putU32(out, 0);                                                  // bytesPlane4-7
  for (const Sample& s : samples) {
    putU32(out, s.bitOffset | (s.bitLength << 16) | (s.channel << 24));
    putU32(out, 0);  // samplePosition 0,0,0,0
    putU32(out, s.lower);
    putU32(out, s.upper);
  }
  return out;
}

std::uint64_t lcm4(std::uint64_t texelBytes) { return std::lcm<std::uint64_t>(texelBytes, 4); }

void putKeyValues(std::string& out, const KeyValues& keyValues) {
  for (const auto& [key, value] : keyValues) {
    putU32(out, static_cast<std::uint32_t>(key.size() + 1 + value.size()));
    out += key;
    out.push_back('\0');
    out += value;
    padTo(out, 4);
  }
}

}  // namespace

std::string encodeKtx2(const Texture& texture, TexelFormat format, const KeyValues& keyValues, EncodingTally& tally) {
  const VkFormatRow& vk = vkRow(format);
  const std::uint64_t levels = static_cast<std::uint64_t>(texture.levelCount());
  const std::string dfd = dataFormatDescriptor(format);
  KeyValues sorted = keyValues;  // the specification: sorted by the keys' code points
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string kvd;
  putKeyValues(kvd, sorted);

  const std::uint64_t dfdOffset = kHeaderBytes + kLevelEntryBytes * levels;
  const std::uint64_t kvdOffset = dfdOffset + dfd.size();
  // Level data, smallest level first, each aligned to lcm(texel block size, 4).
  const std::uint64_t alignment = lcm4(static_cast<std::uint64_t>(bytesPerTexel(format)));
  std::string data;
  std::uint64_t dataStart = kvdOffset + kvd.size();
  dataStart = (dataStart + alignment - 1) / alignment * alignment;
  std::vector<std::uint64_t> offsets(levels), lengths(levels);
  for (std::uint64_t k = levels; k-- > 0;) {
    while ((dataStart + data.size()) % alignment != 0) data.push_back('\0');
    offsets[k] = dataStart + data.size();
    appendLevel(data, texture.levels[k], format, 1, tally);
    lengths[k] = dataStart + data.size() - offsets[k];
  }

  std::string out(reinterpret_cast<const char*>(kIdentifier), sizeof kIdentifier);
  putU32(out, vk.vkFormat);
  putU32(out, vk.typeSize);
  putU32(out, static_cast<std::uint32_t>(texture.width()));
  putU32(out, static_cast<std::uint32_t>(texture.height()));
  putU32(out, 0);  // pixelDepth
  putU32(out, 0);  // layerCount: not an array
  putU32(out, static_cast<std::uint32_t>(texture.faceCount()));
  putU32(out, static_cast<std::uint32_t>(levels));
  putU32(out, 0);  // supercompressionScheme: none
  putU32(out, static_cast<std::uint32_t>(dfdOffset));
  putU32(out, static_cast<std::uint32_t>(dfd.size()));
  putU32(out, kvd.empty() ? 0 : static_cast<std::uint32_t>(kvdOffset));
  putU32(out, static_cast<std::uint32_t>(kvd.size()));
  putU64(out, 0);  // sgdByteOffset
  putU64(out, 0);  // sgdByteLength
  for (std::uint64_t k = 0; k < levels; ++k) {
    putU64(out, offsets[k]);
    putU64(out, lengths[k]);
    putU64(out, lengths[k]);  // uncompressedByteLength
  }
  out += dfd;
  out += kvd;
  out.resize(dataStart, '\0');  // mipPadding before the first (smallest) level
  out += data;
  return out;
}

ParsedTexture parseKtx2(std::string_view bytes, const std::string& label) {
  const ByteReader in(bytes, label);
  in.requireRange(0, kHeaderBytes, "the KTX2 header");
  if (std::memcmp(bytes.data(), kIdentifier, sizeof kIdentifier) != 0) in.fail("not a KTX2 file (bad identifier)");
  const std::uint32_t vkFormat = in.u32(12, "vkFormat"), typeSize = in.u32(16, "typeSize");
  const std::uint64_t width = in.u32(20, "pixelWidth"), height = in.u32(24, "pixelHeight");
  const std::uint32_t depth = in.u32(28, "pixelDepth"), layers = in.u32(32, "layerCount");
  const std::uint64_t faces = in.u32(36, "faceCount");
  const std::uint64_t levels = std::max<std::uint32_t>(1, in.u32(40, "levelCount"));
  const std::uint32_t scheme = in.u32(44, "supercompressionScheme");
  const VkFormatRow* vk = nullptr;
  for (const auto& r : kVkFormats)
    if (r.vkFormat == vkFormat) vk = &r;
  if (!vk) {
    in.fail("unsupported vkFormat " + std::to_string(vkFormat) +
            " (brdfbake reads R16G16B16A16_SFLOAT, R32G32B32A32_SFLOAT, R16G16B16_SFLOAT, R32G32B32_SFLOAT, "
            "E5B9G9R9_UFLOAT_PACK32 and B10G11R11_UFLOAT_PACK32)");
  }
  if (typeSize != vk->typeSize) {
    in.fail("typeSize " + std::to_string(typeSize) + " does not match " + vk->name + " (" +
            std::to_string(vk->typeSize) + ")");
  }
  if (scheme != 0) in.fail("supercompressed (scheme " + std::to_string(scheme) + ") KTX2 files are not supported");
  if (depth != 0) in.fail("3-D textures are not supported (pixelDepth " + std::to_string(depth) + ")");
  if (layers != 0) in.fail("array textures are not supported (layerCount " + std::to_string(layers) + ")");
  checkShape(in, width, std::max<std::uint64_t>(1, height), faces, levels);

  const std::uint64_t indexEnd = kHeaderBytes + kLevelEntryBytes * levels;
  in.requireRange(kHeaderBytes, kLevelEntryBytes * levels, "the level index");
  // Data Format Descriptor: within the file, after the index, its total size its length.
  const std::uint64_t dfdOffset = in.u32(48, "dfdByteOffset"), dfdLength = in.u32(52, "dfdByteLength");
  in.requireRange(dfdOffset, dfdLength, "the data format descriptor");
  if (dfdLength < 4 + 24 || dfdOffset < indexEnd) in.fail("the data format descriptor is misplaced or too short");
  if (in.u32(dfdOffset, "dfdTotalSize") != dfdLength) in.fail("dfdTotalSize differs from dfdByteLength");
  const std::uint32_t bytesPlane0 = in.u32(dfdOffset + 4 + 16, "bytesPlane0") & 0xFF;
  if (bytesPlane0 != static_cast<std::uint32_t>(bytesPerTexel(vk->format))) {
    in.fail("the data format descriptor says " + std::to_string(bytesPlane0) + " bytes per texel, " + vk->name +
            " has " + std::to_string(bytesPerTexel(vk->format)));
  }
  const std::uint64_t sgdLength = in.u64(72, "sgdByteLength");
  if (sgdLength != 0) in.fail("supercompression global data without supercompression");

  ParsedTexture parsed;
  parsed.header.container = TextureContainer::Ktx2;
  parsed.header.format = vk->format;
  parsed.header.width = static_cast<int>(width);
  parsed.header.height = static_cast<int>(std::max<std::uint64_t>(1, height));
  parsed.header.faces = static_cast<int>(faces);
  parsed.header.levels = static_cast<int>(levels);
  const std::uint64_t kvdOffset = in.u32(56, "kvdByteOffset"), kvdLength = in.u32(60, "kvdByteLength");
  if (kvdLength > 0) {
    const KeyValues keyValues = parseKeyValues(in, kvdOffset, kvdLength);
    applyKeyValues(parsed, keyValues, in, false);
  }

  const std::uint64_t texel = static_cast<std::uint64_t>(bytesPerTexel(vk->format));
  for (std::uint64_t k = 0; k < levels; ++k) {
    const std::uint64_t entry = kHeaderBytes + kLevelEntryBytes * k;
    const std::uint64_t offset = in.u64(entry, "level offset"), length = in.u64(entry + 8, "level length");
    const std::uint64_t uncompressed = in.u64(entry + 16, "level uncompressed length");
    const std::uint64_t w = levelSize(width, static_cast<int>(k));
    const std::uint64_t h = levelSize(parsed.header.height, static_cast<int>(k));
    const std::uint64_t faceBytes = w * h * texel;
    const std::string name = "level " + std::to_string(k);
    if (length != faceBytes * faces || uncompressed != length) {
      in.fail(name + " has " + std::to_string(length) + " bytes (uncompressed " + std::to_string(uncompressed) +
              "), but " + std::to_string(faces) + " face(s) of " + std::to_string(w) + " x " + std::to_string(h) +
              " texels of " + std::to_string(texel) + " bytes need " + std::to_string(faceBytes * faces));
    }
    in.requireRange(offset, length, name);
    if (offset < indexEnd) in.fail(name + " overlaps the header");
    parsed.images.emplace_back();
    for (std::uint64_t f = 0; f < faces; ++f) parsed.images.back().push_back({offset + f * faceBytes, w * texel});
  }
  return parsed;
}

}  // namespace brdfbake::texture_detail
