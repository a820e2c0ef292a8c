#pragma once
// Internal to maps/: the byte layouts of KTX2 (ktx2.cpp), KTX1 (ktx1.cpp) and DDS (dds.cpp) behind
// texture.hpp. A parser checks a container's header and sections against the file's size and
// returns where each (level, face) image lies; texture.cpp decodes the texels. An encoder lays a
// validated texture out.
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/texture.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace brdfbake::texture_detail {

/// Where one face image of one level lies: its first byte, and the bytes from one row to the next.
struct ImageSpan {
  std::uint64_t offset = 0;
  std::uint64_t rowPitch = 0;
};

/// A parsed container: its header and the span of every (level, face) image, level 0 first.
struct ParsedTexture {
  TextureHeader header;
  std::vector<std::vector<ImageSpan>> images;
  bool rowsUp = false;  ///< KTXorientation "ru" on a 2-D texture: row 0 is the bottom row
};

ParsedTexture parseKtx2(std::string_view bytes, const std::string& label);
ParsedTexture parseKtx1(std::string_view bytes, const std::string& label);
ParsedTexture parseDds(std::string_view bytes, const std::string& label);

/// Key/value entries to write (key, value bytes including any NUL), in the order given.
using KeyValues = std::vector<std::pair<std::string, std::string>>;

/// Encoders of a validated texture; `tally` counts what encoding changed.
std::string encodeKtx2(const Texture& texture, TexelFormat format, const KeyValues& keyValues, EncodingTally& tally);
std::string encodeKtx1(const Texture& texture, TexelFormat format, const KeyValues& keyValues, EncodingTally& tally);
std::string encodeDds(const Texture& texture, TexelFormat format, EncodingTally& tally);

/// max(1, size >> level).
inline std::uint64_t levelSize(std::uint64_t size, int level) {
  return level >= 63 ? 1 : std::max<std::uint64_t>(1, size >> level);
}
/// floor(log2(max(width, height))) + 1.
int maxLevelCount(std::uint64_t width, std::uint64_t height);

/// Appends an encoded image, rows padded to `rowAlignment` bytes.
void appendImage(std::string& out, const Image& image, TexelFormat format, int rowAlignment, EncodingTally& tally);
/// appendImage of every face of one level.
void appendLevel(std::string& out, const std::vector<Image>& faces, TexelFormat format, int rowAlignment,
                 EncodingTally& tally);

/// Little-endian appends.
void putU16(std::string& out, std::uint16_t v);
void putU32(std::string& out, std::uint32_t v);
void putU64(std::string& out, std::uint64_t v);
void padTo(std::string& out, std::size_t alignment);

/// Bounds-checked little-endian reads from a file's bytes; every failure is Error(InvalidInput)
/// "<label>: <what> ...".
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::string label) : bytes_(bytes), label_(std::move(label)) {}
  std::uint64_t size() const { return bytes_.size(); }
  const std::string& label() const { return label_; }
  std::string_view bytes() const { return bytes_; }
  /// Throws "<label>: truncated: <what> needs bytes [offset, offset + length) but the file has N bytes".
  void requireRange(std::uint64_t offset, std::uint64_t length, const std::string& what) const;
  std::uint16_t u16(std::uint64_t offset, const std::string& what) const;
  std::uint32_t u32(std::uint64_t offset, const std::string& what) const;
  std::uint64_t u64(std::uint64_t offset, const std::string& what) const;
  /// Error(InvalidInput) "<label>: <message>".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string_view bytes_;
  std::string label_;
};

/// Parses KTX key/value data at [offset, offset + length): entries of a UInt32 length, the key
/// and its NUL, the value, then padding to 4 bytes. Refuses entries beyond the section, keys
/// without NUL, repeated keys. Returns (key, value with one trailing NUL removed).
KeyValues parseKeyValues(const ByteReader& in, std::uint64_t offset, std::uint64_t length);

/// Applies the key/value entries brdfbake understands to `parsed`: "brdfbake.metadata" (JSON) and
/// "KTXorientation" (KTX2 "rd"/"ru", KTX1 "S=r,T=d"/"S=r,T=u"; "ru" only on 2-D textures).
void applyKeyValues(ParsedTexture& parsed, const KeyValues& keyValues, const ByteReader& in, bool ktx1);

/// Checks sizes shared by every container: width and height in [1, kMaxTextureSize], 1 or 6
/// faces (square for 6), levels in [1, maxLevelCount].
void checkShape(const ByteReader& in, std::uint64_t width, std::uint64_t height, std::uint64_t faces,
                std::uint64_t levels);

}  // namespace brdfbake::texture_detail
