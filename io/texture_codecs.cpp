// What KTX2, KTX1 and DDS share (texture_codecs.hpp): bounds-checked reads, little-endian writes,
// key/value data, shape checks, encoded levels.
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_text.hpp>

#include <algorithm>
#include <set>

#include "texture_codecs.hpp"

namespace brdfbake::texture_detail {

int maxLevelCount(std::uint64_t width, std::uint64_t height) {
  std::uint64_t size = std::max(width, height);
  int levels = 1;
  while (size > 1) size >>= 1, ++levels;
  return levels;
}

void putU16(std::string& out, std::uint16_t v) {
  out.push_back(static_cast<char>(v & 0xFF));
  out.push_back(static_cast<char>(v >> 8));
}
void putU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void putU64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void padTo(std::string& out, std::size_t alignment) {
  while (out.size() % alignment != 0) out.push_back('\0');
}

void appendImage(std::string& out, const Image& image, TexelFormat format, int rowAlignment, EncodingTally& tally) {
  const std::size_t rowBytes =
      static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(bytesPerTexel(format));
  const std::size_t pitch = (rowBytes + rowAlignment - 1) / rowAlignment * rowAlignment;
  for (int y = 0; y < image.height(); ++y) {
    const std::size_t start = out.size();
    out.resize(start + pitch, '\0');
    encodeTexels(image.data() + image.index(0, y), static_cast<std::size_t>(image.width()), format,
                 reinterpret_cast<unsigned char*>(out.data() + start), tally);
  }
}

void appendLevel(std::string& out, const std::vector<Image>& faces, TexelFormat format, int rowAlignment,
                 EncodingTally& tally) {
  for (const Image& face : faces) appendImage(out, face, format, rowAlignment, tally);
}

void ByteReader::fail(const std::string& message) const {
  throw Error(Error::Kind::InvalidInput, label_ + ": " + message);
}

void ByteReader::requireRange(std::uint64_t offset, std::uint64_t length, const std::string& what) const {
  if (offset > bytes_.size() || length > bytes_.size() - offset) {
    fail("truncated or corrupt: " + what + " needs bytes " + std::to_string(offset) + " to " +
         (length > UINT64_MAX - offset ? std::string("beyond 2^64") : std::to_string(offset + length)) +
         ", but the file has " + std::to_string(bytes_.size()) + " bytes");
  }
}

std::uint16_t ByteReader::u16(std::uint64_t offset, const std::string& what) const {
  requireRange(offset, 2, what);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data() + offset);
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

std::uint32_t ByteReader::u32(std::uint64_t offset, const std::string& what) const {
  requireRange(offset, 4, what);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data() + offset);
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

std::uint64_t ByteReader::u64(std::uint64_t offset, const std::string& what) const {
  return u32(offset, what) | (static_cast<std::uint64_t>(u32(offset + 4, what)) << 32);
}

KeyValues parseKeyValues(const ByteReader& in, std::uint64_t offset, std::uint64_t length) {
  in.requireRange(offset, length, "the key/value data");
  KeyValues out;
  std::set<std::string> keys;
  const std::uint64_t end = offset + length;
  std::uint64_t at = offset;
  while (at < end) {
    const std::string entry = "key/value entry " + std::to_string(out.size());
    if (end - at < 4) in.fail(entry + ": truncated inside the key/value data");
    const std::uint64_t size = in.u32(at, entry);
    at += 4;
    if (size < 2 || size > end - at) {
      in.fail(entry + ": length " + std::to_string(size) + " does not fit the " + std::to_string(end - at) +
              " bytes left of the key/value data");
    }
    const std::string_view text = in.bytes().substr(at, size);
    const std::size_t nul = text.find('\0');
    if (nul == std::string_view::npos || nul == 0) in.fail(entry + ": the key is empty or has no NUL terminator");
    std::string key(text.substr(0, nul));
    std::string value(text.substr(nul + 1));
    if (!value.empty() && value.back() == '\0') value.pop_back();
    if (!keys.insert(key).second) in.fail(entry + ": key '" + shortenForMessage(key, 64) + "' appears twice");
    out.emplace_back(std::move(key), std::move(value));
    at += (size + 3) / 4 * 4;  // valuePadding
  }
  return out;
}

void applyKeyValues(ParsedTexture& parsed, const KeyValues& keyValues, const ByteReader& in, bool ktx1) {
  for (const auto& [key, value] : keyValues) {
    const bool text = value.find('\0') == std::string::npos;
    if (text) parsed.header.keyValues.emplace_back(key, value);
    if (key == kMetadataKey) {
      nlohmann::json metadata = parseJsonText(value, in.label() + " (key/value entry " + kMetadataKey + ")");
      if (!metadata.is_object()) in.fail(std::string(kMetadataKey) + " is not a JSON object");
      parsed.header.metadata = std::move(metadata);
    } else if (key == "KTXorientation") {
      const std::string down = ktx1 ? "S=r,T=d" : "rd", up = ktx1 ? "S=r,T=u" : "ru";
      // KTX1 writers append ",R=i" or similar for 3-D; only the first two axes matter here.
      const std::string axes = value.substr(0, down.size());
      if (axes == up && parsed.header.faces == 1) {
        parsed.rowsUp = true;
      } else if (axes != down) {
        in.fail("KTXorientation '" + shortenForMessage(value, 64) + "' is not supported (brdfbake reads '" + down +
                "'" + (parsed.header.faces == 1 ? " and '" + up + "'" : std::string(" for cube maps")) + ")");
      }
    }
  }
}

void checkShape(const ByteReader& in, std::uint64_t width, std::uint64_t height, std::uint64_t faces,
                std::uint64_t levels) {
  const std::uint64_t limit = static_cast<std::uint64_t>(kMaxTextureSize);
  if (width < 1 || height < 1 || width > limit || height > limit) {
    in.fail("size " + std::to_string(width) + " x " + std::to_string(height) + " is outside 1 to " +
            std::to_string(limit) + " texels");
  }
  if (faces != 1 && faces != 6) in.fail("face count " + std::to_string(faces) + " (a texture has 1 face, a cube 6)");
  if (faces == 6 && width != height) {
    in.fail("cube map faces must be square, got " + std::to_string(width) + " x " + std::to_string(height));
  }
  const int most = maxLevelCount(width, height);
  if (levels > static_cast<std::uint64_t>(most)) {
    in.fail(std::to_string(levels) + " mip levels, more than a " + std::to_string(width) + " x " +
            std::to_string(height) + " texture allows (" + std::to_string(most) + ")");
  }
}

}  // namespace brdfbake::texture_detail
