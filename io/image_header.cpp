// Image headers read and checked before OpenImageIO sees the file (image_header.hpp).
//
// The bound on samples: a codec cannot decode more raw bytes than its compression can expand one
// byte of file into. Deflate (PNG, OpenEXR ZIP/ZIPS/PXR24, TIFF Deflate) expands at most 1032:1 (a
// 258-byte match in 2 bits); run-length codes 64:1 (OpenEXR RLE, TIFF PackBits: 128 bytes in 2) or
// 16 pixels per byte (Radiance RLE, 4-byte pixels); TIFF LZW at most about 1366:1 (4094 codes of
// at most 12 bits between table resets decode to at most 4094 * 4095 / 2 bytes); OpenEXR's PIZ and
// B44 below that of deflate (PIZ's run codes pack 256 values in 10 bits: 409.6:1), DWA at most
// PIZ's times deflate's (it deflates Huffman-coded parts). Formats or compressions not listed are
// refused.
#include "image_header.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace brdfbake::image_header {
namespace {

constexpr double kDeflate = 1032.0;
constexpr double kRunLength = 64.0;
constexpr double kLzw = 1366.0;
// DWAA/DWAB deflate what PIZ's Huffman coder (up to 409.6:1 with its run codes) has packed.
constexpr double kDwa = 409.6 * kDeflate;

class Bytes {
 public:
  Bytes(std::string_view data, const std::string& label, bool bigEndian = false)
      : data_(data), label_(label), big_(bigEndian) {}
  [[noreturn]] void fail(const std::string& message) const {
    throw Error(Error::Kind::InvalidInput, label_ + ": " + message);
  }
  void need(std::uint64_t at, std::uint64_t count, const char* what) const {
    if (at > data_.size() || count > data_.size() - at) fail(std::string("header ends inside ") + what);
  }
  std::uint64_t unsignedAt(std::uint64_t at, int size, const char* what) const {
    need(at, static_cast<std::uint64_t>(size), what);
    std::uint64_t value = 0;
    for (int i = 0; i < size; ++i) {
      const std::uint64_t byte = static_cast<unsigned char>(data_[at + static_cast<std::uint64_t>(i)]);
      value |= big_ ? byte << (8 * (size - 1 - i)) : byte << (8 * i);
    }
    return value;
  }
  std::int32_t int32At(std::uint64_t at, const char* what) const {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(unsignedAt(at, 4, what)));
  }
  std::string_view data() const { return data_; }
  const std::string& label() const { return label_; }

 private:
  std::string_view data_;
  const std::string& label_;
  bool big_;
};

std::string sizeText(std::int64_t w, std::int64_t h) { return std::to_string(w) + " x " + std::to_string(h); }

// A whole number of any size (a count of bytes may pass 2^63: 2147483647^2 x 16).
std::string wholeText(double value) {
  char text[400];
  std::snprintf(text, sizeof text, "%.0f", value);
  return text;
}

// ---- OpenEXR (openexr.com, "OpenEXR File Layout") -----------------------------------------------

struct ExrHeader {
  std::int64_t width = 0, height = 0;
  double bytesPerPixel = 0.0;
  int channels = 0, compression = -1;
  bool tiled = false;
  std::uint32_t tileWidth = 0, tileHeight = 0;
  int levelMode = 0, roundingMode = 0;
  bool hasDataWindow = false;
};

// A NUL-terminated name of at most `limit` bytes at `at`; moves `at` past it.
std::string_view exrName(const Bytes& b, std::uint64_t& at, std::size_t limit, const char* what) {
  const std::string_view data = b.data();
  const std::size_t end = at < data.size() ? data.find('\0', at) : std::string_view::npos;
  if (end == std::string_view::npos) b.fail(std::string("header ends inside ") + what);
  if (end - at > limit) b.fail(std::string(what) + " longer than " + std::to_string(limit) + " bytes");
  const std::string_view name = data.substr(at, end - at);
  at = end + 1;
  return name;
}

void readExrChannels(const Bytes& b, std::uint64_t at, std::uint64_t end, ExrHeader& h) {
  while (at < end && b.data()[at] != '\0') {
    exrName(b, at, 255, "a channel name");
    const std::int32_t type = b.int32At(at, "a channel"), xs = b.int32At(at + 8, "a channel"),
                       ys = b.int32At(at + 12, "a channel");
    at += 16;
    if (type < 0 || type > 2) b.fail("channel pixel type " + std::to_string(type) + " is not uint, half or float");
    if (xs < 1 || ys < 1) b.fail("channel sampling must be >= 1");
    h.bytesPerPixel += (type == 1 ? 2.0 : 4.0) / (static_cast<double>(xs) * ys);
    if (++h.channels > 1024) b.fail("more than 1024 channels");
  }
  if (at > end) b.fail("the channel list runs past its attribute");
}

// Levels of a tiled file: 1, or up to 32 per axis for MIP and RIP maps.
int exrLevels(std::int64_t size, int roundingMode) {
  int levels = 1;
  while (size > 1) {
    size = roundingMode == 1 ? (size + 1) / 2 : size / 2;
    ++levels;
  }
  return levels;
}

// Chunks (scanline blocks or tiles, each with an 8-byte entry in the offset table) of the file.
double exrChunks(const ExrHeader& h) {
  if (!h.tiled) {
    static const int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    return std::ceil(static_cast<double>(h.height) / kLines[h.compression]);
  }
  const int xLevels = h.levelMode == 0 ? 1 : exrLevels(h.width, h.roundingMode);
  const int yLevels = h.levelMode == 0 ? 1 : exrLevels(h.height, h.roundingMode);
  double chunks = 0.0;
  auto levelSize = [&](std::int64_t size, int level) {
    for (int i = 0; i < level; ++i) size = h.roundingMode == 1 ? (size + 1) / 2 : size / 2;
    return static_cast<double>(std::max<std::int64_t>(size, 1));
  };
  auto tiles = [&](int lx, int ly) {
    return std::ceil(levelSize(h.width, lx) / h.tileWidth) * std::ceil(levelSize(h.height, ly) / h.tileHeight);
  };
  if (h.levelMode == 2) {  // RIP map: every pair of levels
    for (int ly = 0; ly < yLevels; ++ly)
      for (int lx = 0; lx < xLevels; ++lx) chunks += tiles(lx, ly);
  } else {
    for (int l = 0; l < std::max(xLevels, yLevels); ++l)
      chunks += tiles(std::min(l, xLevels - 1), std::min(l, yLevels - 1));
  }
  return chunks;
}

void readExrAttribute(const Bytes& b, std::string_view name, std::string_view type, std::uint64_t at,
                      std::uint64_t size, ExrHeader& h) {
  if (name == "channels" && type == "chlist") {
    readExrChannels(b, at, at + size, h);
  } else if (name == "dataWindow" && type == "box2i" && size == 16) {
    const std::int64_t x0 = b.int32At(at, "dataWindow"), y0 = b.int32At(at + 4, "dataWindow");
    const std::int64_t x1 = b.int32At(at + 8, "dataWindow"), y1 = b.int32At(at + 12, "dataWindow");
    h.width = x1 - x0 + 1;
    h.height = y1 - y0 + 1;
    h.hasDataWindow = true;
    if (h.width < 1 || h.height < 1) b.fail("empty data window " + sizeText(h.width, h.height));
  } else if (name == "compression" && type == "compression" && size == 1) {
    h.compression = static_cast<int>(b.unsignedAt(at, 1, "compression"));
    if (h.compression > 9) b.fail("unknown compression " + std::to_string(h.compression));
  } else if (name == "tiles" && type == "tiledesc" && size == 9) {
    h.tileWidth = static_cast<std::uint32_t>(b.unsignedAt(at, 4, "tiles"));
    h.tileHeight = static_cast<std::uint32_t>(b.unsignedAt(at + 4, 4, "tiles"));
    const unsigned mode = static_cast<unsigned>(b.unsignedAt(at + 8, 1, "tiles"));
    h.levelMode = static_cast<int>(mode & 0xFu);
    h.roundingMode = static_cast<int>(mode >> 4);
    if (h.tileWidth < 1 || h.tileHeight < 1 || h.tileWidth > (1u << 20) || h.tileHeight > (1u << 20) ||
        h.levelMode > 2 || h.roundingMode > 1)
      b.fail("bad tile description");
  }
}

Claim checkExr(const Bytes& b, std::uintmax_t fileBytes) {
  const std::uint32_t version = static_cast<std::uint32_t>(b.unsignedAt(4, 4, "the version"));
  if ((version & 0xFFu) != 2) b.fail("OpenEXR version " + std::to_string(version & 0xFFu) + " is not 2");
  if (version & 0x800u) b.fail("deep OpenEXR data is not an image brdfbake reads");
  if (version & 0x1000u) b.fail("multi-part OpenEXR files are not read; write a single-part file");
  const std::size_t nameLimit = (version & 0x400u) ? 255 : 31;
  ExrHeader h;
  h.tiled = (version & 0x200u) != 0;
  std::uint64_t at = 8;
  for (int count = 0;; ++count) {
    if (count > 10000) b.fail("more than 10000 header attributes");
    const std::string_view name = exrName(b, at, nameLimit, "an attribute name");
    if (name.empty()) break;
    const std::string_view type = exrName(b, at, nameLimit, "an attribute type");
    const std::int32_t size = b.int32At(at, "an attribute size");
    at += 4;
    if (size < 0 || static_cast<std::uint64_t>(size) > fileBytes - std::min<std::uint64_t>(at, fileBytes)) {
      b.fail("attribute '" + printable(name, 40) + "' claims " + std::to_string(size) + " bytes, more than the " +
             std::to_string(fileBytes) + "-byte file has after it");
    }
    b.need(at, static_cast<std::uint64_t>(size), "an attribute value");
    readExrAttribute(b, name, type, at, static_cast<std::uint64_t>(size), h);
    at += static_cast<std::uint64_t>(size);
  }
  if (!h.hasDataWindow || h.compression < 0 || h.channels == 0 || (h.tiled && h.tileWidth == 0)) {
    b.fail("the header lacks dataWindow, compression, channels or (tiled) tiles");
  }
  const double chunks = exrChunks(h);
  if (8.0 * chunks > static_cast<double>(fileBytes) - static_cast<double>(at)) {
    b.fail("a " + sizeText(h.width, h.height) + " image has " + wholeText(chunks) +
           " chunks, whose offset table alone needs more than the " + std::to_string(fileBytes) + "-byte file");
  }
  static const double kExpansion[] = {1.0,        kRunLength, kDeflate, kDeflate, kDeflate, kDeflate * 4.0 / 3.0,
                                      32.0 / 3.0, 32.0 / 3.0, kDwa,     kDwa};
  const double levels = h.tiled && h.levelMode != 0 ? 4.0 / 3.0 : 1.0;  // all MIP levels: below 4/3 of level 0
  return {Format::OpenExr,
          h.width,
          h.height,
          h.channels,
          static_cast<double>(h.width) * static_cast<double>(h.height) * h.bytesPerPixel *
              (h.levelMode == 2 ? 4.0 : levels),
          kExpansion[h.compression]};
}

// ---- PNG (ISO/IEC 15948: the IHDR chunk first) ---------------------------------------------------

Claim checkPng(const Bytes& b) {
  if (b.data().size() < 16 || b.data().compare(12, 4, "IHDR") != 0)
    b.fail("the PNG does not start with its IHDR chunk");
  const std::int64_t width = static_cast<std::int64_t>(b.unsignedAt(16, 4, "IHDR"));
  const std::int64_t height = static_cast<std::int64_t>(b.unsignedAt(20, 4, "IHDR"));
  const int depth = static_cast<int>(b.unsignedAt(24, 1, "IHDR")),
            color = static_cast<int>(b.unsignedAt(25, 1, "IHDR"));
  const int interlace = static_cast<int>(b.unsignedAt(28, 1, "IHDR"));
  int samples = 0;
  switch (color) {
    case 0:
      samples = 1;
      break;  // grey
    case 2:
      samples = 3;
      break;  // RGB
    case 3:
      samples = 1;
      break;  // palette index
    case 4:
      samples = 2;
      break;  // grey, alpha
    case 6:
      samples = 4;
      break;  // RGBA
    default:
      b.fail("PNG colour type " + std::to_string(color) + " is not valid");
  }
  if (width < 1 || height < 1 || width > 0x7FFFFFFF || height > 0x7FFFFFFF)
    b.fail("PNG size " + sizeText(width, height) + " is not valid");
  if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16) b.fail("PNG bit depth is not valid");
  // Each row: one filter byte and its packed samples (Adam7 interlacing adds at most 7 filter bytes).
  const double row = 1.0 + std::ceil(static_cast<double>(width) * samples * depth / 8.0);
  const double raw = static_cast<double>(height) * row + (interlace ? 7.0 * static_cast<double>(height) : 0.0);
  return {Format::Png, width, height, color == 3 ? 4 : samples, raw, kDeflate};
}

// ---- Radiance HDR (Ward, "Real Pixels", Graphics Gems II): text lines, then "-Y H +X W" ---------

Claim checkHdr(const Bytes& b) {
  const std::string_view data = b.data();
  std::size_t at = 0;
  bool blank = false;
  for (int line = 0; line < 1000 && !blank; ++line) {
    const std::size_t end = data.find('\n', at);
    if (end == std::string_view::npos) b.fail("the Radiance header does not end (no blank line)");
    blank = end == at;
    if (data.substr(at, end - at).rfind("FORMAT=", 0) == 0 && data.substr(at, end - at) != "FORMAT=32-bit_rle_rgbe" &&
        data.substr(at, end - at) != "FORMAT=32-bit_rle_xyze")
      b.fail("unknown Radiance pixel format");
    at = end + 1;
  }
  if (!blank) b.fail("the Radiance header has more than 1000 lines");
  const std::size_t end = data.find('\n', at);
  if (end == std::string_view::npos || end - at > 64) b.fail("the Radiance resolution line is missing");
  const std::string line(data.substr(at, end - at));
  char first[3] = {}, second[3] = {};
  long long a = 0, c = 0;
  int used = 0;
  if (std::sscanf(line.c_str(), "%2s %lld %2s %lld%n", first, &a, second, &c, &used) != 4 ||
      static_cast<std::size_t>(used) != line.size() || (first[1] != 'Y' && first[1] != 'X') ||
      (first[0] != '-' && first[0] != '+') || (second[0] != '-' && second[0] != '+') || second[1] == first[1] ||
      (second[1] != 'Y' && second[1] != 'X'))
    b.fail("the Radiance resolution line is not \"-Y H +X W\"");
  const std::int64_t height = first[1] == 'Y' ? a : c, width = first[1] == 'Y' ? c : a;
  if (width < 1 || height < 1 || width > 0x7FFFFFFF || height > 0x7FFFFFFF)
    b.fail("Radiance size " + sizeText(width, height) + " is not valid");
  // 4 bytes per pixel, run-length coded down to 1/16 of a byte each (128-byte runs in 2 bytes).
  return {Format::RadianceHdr, width, height, 3, 4.0 * static_cast<double>(width) * static_cast<double>(height),
          kRunLength};
}

// ---- TIFF (TIFF 6.0 and BigTIFF: the first image file directory) ---------------------------------

Claim checkTiff(const std::string_view data, std::uintmax_t fileBytes, const std::string& label) {
  const bool big = data[0] == 'M';
  const Bytes b(data, label, big);
  const std::uint64_t magic = b.unsignedAt(2, 2, "the TIFF header");
  if (magic != 42 && magic != 43) b.fail("not a TIFF file (version " + std::to_string(magic) + ")");
  const bool bigTiff = magic == 43;
  const int offsetSize = bigTiff ? 8 : 4, entrySize = bigTiff ? 20 : 12, countSize = bigTiff ? 8 : 2;
  const std::uint64_t directory = b.unsignedAt(bigTiff ? 8 : 4, offsetSize, "the TIFF header");
  const std::uint64_t entries = b.unsignedAt(directory, countSize, "the first TIFF directory");
  if (entries > 4096) b.fail("the first TIFF directory has more than 4096 entries");
  b.need(directory + static_cast<std::uint64_t>(countSize), entries * static_cast<std::uint64_t>(entrySize),
         "the first TIFF directory");
  std::int64_t width = 0, height = 0;
  std::uint64_t bits = 1, samples = 1, compression = 1;
  for (std::uint64_t i = 0; i < entries; ++i) {
    const std::uint64_t entry =
        directory + static_cast<std::uint64_t>(countSize) + i * static_cast<std::uint64_t>(entrySize);
    const std::uint64_t tag = b.unsignedAt(entry, 2, "a TIFF entry"), type = b.unsignedAt(entry + 2, 2, "a TIFF entry");
    const std::uint64_t count = b.unsignedAt(entry + 4, countSize == 2 ? 4 : 8, "a TIFF entry");
    const std::uint64_t valueAt = entry + (bigTiff ? 12 : 8);
    // Values that do not fit in the entry lie elsewhere in the file: they cannot be more than it.
    static const int kTypeSizes[] = {0, 1, 1, 2, 4, 8, 1, 1, 2, 4, 8, 4, 8, 4, 0, 0, 8, 8, 8};
    const int typeSize = type < 19 ? kTypeSizes[type] : 0;
    if (typeSize > 0 && count > fileBytes / static_cast<std::uint64_t>(typeSize)) {
      b.fail("TIFF tag " + std::to_string(tag) + " claims " + std::to_string(count) + " values, more than the " +
             std::to_string(fileBytes) + "-byte file holds");
    }
    const int size = type == 3 ? 2 : type == 4 ? 4 : type == 16 ? 8 : 0;  // SHORT, LONG, LONG8
    if (size == 0 || count == 0) continue;
    // The first value: in the entry when the values fit there, else at the offset the entry gives.
    const std::uint64_t first = static_cast<std::uint64_t>(size) * count <= static_cast<std::uint64_t>(offsetSize)
                                    ? valueAt
                                    : b.unsignedAt(valueAt, offsetSize, "a TIFF entry");
    const std::uint64_t value = b.unsignedAt(first, size, "a TIFF value");
    if (tag == 256) width = static_cast<std::int64_t>(std::min<std::uint64_t>(value, 1ull << 40));
    if (tag == 257) height = static_cast<std::int64_t>(std::min<std::uint64_t>(value, 1ull << 40));
    if (tag == 258) bits = value;
    if (tag == 259) compression = value;
    if (tag == 277) samples = value;
  }
  if (width < 1 || height < 1) b.fail("the TIFF image size " + sizeText(width, height) + " is not valid");
  if (bits < 1 || bits > 64 || samples < 1 || samples > 64) b.fail("TIFF samples or bits per sample are not valid");
  double expansion = 0.0;
  if (compression == 1) expansion = 1.0;
  if (compression == 5) expansion = kLzw;
  if (compression == 8 || compression == 32946) expansion = kDeflate;
  if (compression == 32773) expansion = kRunLength;
  if (expansion == 0.0) {
    b.fail("TIFF compression " + std::to_string(compression) +
           " is not one brdfbake reads (none, LZW, Deflate or PackBits)");
  }
  return {Format::Tiff,
          width,
          height,
          static_cast<int>(samples),
          static_cast<double>(width) * static_cast<double>(height) * static_cast<double>(samples * bits) / 8.0,
          expansion};
}

}  // namespace

Claim checkHeader(std::string_view bytes, std::uintmax_t fileBytes, const std::string& label) {
  static const char kExr[] = {'\x76', '\x2f', '\x31', '\x01'};
  static const std::string_view kPng("\x89PNG\r\n\x1a\n", 8);
  const Bytes b(bytes, label);
  Claim claim;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), kExr, 4) == 0) {
    claim = checkExr(b, fileBytes);
  } else if (bytes.substr(0, 8) == kPng) {
    claim = checkPng(Bytes(bytes, label, /*bigEndian=*/true));
  } else if (bytes.substr(0, 10) == "#?RADIANCE" || bytes.substr(0, 6) == "#?RGBE") {
    claim = checkHdr(b);
  } else if (bytes.size() >= 4 && (bytes.substr(0, 2) == "II" || bytes.substr(0, 2) == "MM")) {
    claim = checkTiff(bytes, fileBytes, label);
  } else {
    // Io, as when a decoder cannot read a file: nothing here says what the bytes were meant to be.
    throw Error(Error::Kind::Io, label +
                                     ": not an OpenEXR, Radiance HDR, PNG or TIFF file (the image formats "
                                     "brdfbake reads)");
  }
  const double holdable = claim.maxExpansion * static_cast<double>(fileBytes) + 65536.0;
  if (claim.rawBytes > holdable) {
    b.fail("the header says " + sizeText(claim.width, claim.height) + " pixels, more than a " +
           std::to_string(fileBytes) + "-byte file can hold (" + wholeText(claim.rawBytes) +
           " bytes of samples; this kind of file holds at most " + wholeText(claim.maxExpansion) +
           " per byte: truncated or corrupt)");
  }
  const double decoded = static_cast<double>(claim.width) * static_cast<double>(claim.height) * 16.0;
  if (decoded > std::max(kFreeDecodedBytes, kMaxDecodedPerFileByte * static_cast<double>(fileBytes))) {
    b.fail("the header says " + sizeText(claim.width, claim.height) + " pixels, " + wholeText(decoded) +
           " bytes as float RGBA from a " + std::to_string(fileBytes) +
           "-byte file; above 128 MiB brdfbake decodes at most 1024 bytes per byte of file (no real picture "
           "compresses so far: a flat or hostile file; docs/limits.md)");
  }
  return claim;
}

Claim checkHeaderOfFile(const InputFile& file) {
  const std::string head =
      file.read(0, static_cast<std::size_t>(std::min<std::uintmax_t>(file.size(), kMaxHeaderBytes)));
  return checkHeader(head, file.size(), printable(file.path().string()));
}

}  // namespace brdfbake::image_header
