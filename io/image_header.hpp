#pragma once
// What an image file's header claims, read by brdfbake itself before OpenImageIO opens the file:
// OpenImageIO and the codecs below it allocate what a header says (a string attribute of 2 GB, an
// offset table for 2^31 chunks, pixel buffers for 17000 x 17000) before anything else could check
// it. So readImage accepts only the formats whose headers are checked here (OpenEXR, Radiance HDR,
// PNG, TIFF), and refuses a header that claims more than its file can hold.

#include <brdfbake/io/files.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace brdfbake::image_header {

enum class Format { OpenExr, RadianceHdr, Png, Tiff };

/// What the first subimage's header says, as far as the bounds need it.
struct Claim {
  Format format = Format::OpenExr;
  std::int64_t width = 0, height = 0;
  int channels = 0;
  /// Bytes of raw (uncompressed) samples the first subimage decodes to, all MIP levels included.
  double rawBytes = 0.0;
  /// The most raw bytes one byte of this file can hold with its compression (1032 for deflate).
  double maxExpansion = 1.0;
};

/// The most header bytes read (and the most bytes an attribute may have): 16 MiB.
inline constexpr std::size_t kMaxHeaderBytes = std::size_t{16} << 20;

/// Parses the header at the start of `bytes` (the first kMaxHeaderBytes of a file of `fileBytes`
/// bytes) and checks it against the file's length. Throws Error(Io) "<label>: not an OpenEXR, ..."
/// for an unknown format, Error(InvalidInput) "<label>: ..." for a malformed or truncated header, an
/// attribute or table beyond the file, and samples that no file of this length can hold with the
/// header's compression.
Claim checkHeader(std::string_view bytes, std::uintmax_t fileBytes, const std::string& label);

/// Above this many bytes of decoded float RGBA, an image must come from a file of at least 1/1024
/// of that (kMaxDecodedPerFileByte): 128 MiB, a 4096 x 2048 image.
inline constexpr double kFreeDecodedBytes = 128.0 * (1 << 20);
/// Decoded float RGBA bytes (16 per pixel) one byte of file may stand for above kFreeDecodedBytes.
/// Real pictures compress far less (an 8-bit sky about 2:1, 10 decoded bytes per file byte); a
/// file beyond it is a flat or hostile picture that would cost memory out of all proportion.
inline constexpr double kMaxDecodedPerFileByte = 1024.0;

/// Reads the first kMaxHeaderBytes of the open file and calls checkHeader (label: its path, printable).
Claim checkHeaderOfFile(const InputFile& file);

}  // namespace brdfbake::image_header
