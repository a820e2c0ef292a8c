// Format detection, the MERL reader and the format dispatch.
#include <brdfbake/measured/measured_io.hpp>

#include <brdfbake/io/files.hpp>

#include "measured_common.hpp"

#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace brdfbake {

using measured::malformed;

static_assert(std::endian::native == std::endian::little, "the MERL reader assumes a little-endian host");

namespace {

constexpr std::int32_t kMerlDims[3] = {MerlTable::kThetaHalfBins, MerlTable::kThetaDiffBins, MerlTable::kPhiDiffBins};
constexpr std::uintmax_t kMerlHeaderBytes = 3 * sizeof(std::int32_t);
constexpr std::uintmax_t kMerlFileBytes = kMerlHeaderBytes + 3 * sizeof(double) * MerlTable::kBinsPerChannel;

std::array<std::int32_t, 3> merlDims(std::string_view bytes) {
  std::array<std::int32_t, 3> dims{};
  std::memcpy(dims.data(), bytes.data(), kMerlHeaderBytes);
  return dims;
}

bool isMerlHeader(std::string_view bytes) {
  if (bytes.size() < kMerlHeaderBytes) return false;
  const auto dims = merlDims(bytes);
  return dims[0] == kMerlDims[0] && dims[1] == kMerlDims[1] && dims[2] == kMerlDims[2];
}

bool isMatHeader(std::string_view bytes) {
  // MATLAB v5 and v7.3 files open with a 116-byte descriptive text, e.g. "MATLAB 5.0 MAT-file, ...".
  const std::string_view text = bytes.substr(0, 116);
  return text.starts_with("MATLAB ") && text.find("MAT-file") != std::string_view::npos;
}

// ASTM: the first non-blank line is "KEY value" with an upper-case KEY.
bool looksLikeAstm(const std::vector<measured::TextLine>& lines) {
  for (const auto& line : lines) {
    const std::string_view text = measured::trim(line.text);
    if (text.empty()) continue;
    const std::string_view key = text.substr(0, text.find_first_of(" \t"));
    if (!std::isupper(static_cast<unsigned char>(key.front()))) return false;
    for (char c : key)
      if (!(std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
        return false;
    return true;
  }
  return false;
}

// pbrt: after blank lines and '#' comments, the first token is a positive whole number.
bool looksLikePbrt(const std::vector<measured::TextLine>& lines) {
  for (const auto& line : lines) {
    const std::string_view text = measured::trim(line.text.substr(0, line.text.find('#')));
    if (text.empty()) continue;
    const auto count = measured::parseCount(measured::splitWhitespace(text).front());
    return count && *count >= 1;
  }
  return false;
}

}  // namespace

TableFormat detectTableFormat(const std::filesystem::path& path) {
  // The ASTM header and the pbrt wavelength count are near the top; 64 KiB is plenty.
  const std::string prefix = measured::readFilePrefix(path, 64 * 1024);
  if (isMatHeader(prefix)) return TableFormat::Mat;
  if (isMerlHeader(prefix)) return TableFormat::Merl;
  if (prefix.find('\0') == std::string::npos) {
    const std::vector<measured::TextLine> lines = measured::splitLines(prefix);
    if (looksLikeAstm(lines)) return TableFormat::Astm;
    if (looksLikePbrt(lines)) return TableFormat::Pbrt;
  }
  throw malformed(path.string(), 0,
                  "cannot tell the table format from the content: not ASTM (header 'KEY value' lines and VARS), "
                  "pbrt .brdf (number of wavelengths after # comments), MERL .binary (int32 dims 90 90 180) "
                  "or MATLAB .mat (\"MATLAB 5.0 MAT-file\" header)");
}

MerlTable readMerl(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::uintmax_t size = requireInputFile(path, "MERL table");
  if (size != kMerlFileBytes)
    throw malformed(file, 0,
                    "a MERL .binary must be exactly " + std::to_string(kMerlFileBytes) +
                        " bytes (int32 dims 90 90 180, then 3 x 90 x 90 x 180 doubles), this file has " +
                        std::to_string(size));

  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error::atFile(Error::Kind::Io, file, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string header(kMerlHeaderBytes, '\0');
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  const auto dims = merlDims(header);
  if (!in || !isMerlHeader(header))
    throw malformed(file, 0,
                    "MERL header dims are " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                        std::to_string(dims[2]) + ", expected 90 x 90 x 180");

  std::vector<double> stored(3 * MerlTable::kBinsPerChannel);
  in.read(reinterpret_cast<char*>(stored.data()), static_cast<std::streamsize>(stored.size() * sizeof(double)));
  if (!in) throw Error::atFile(Error::Kind::Io, file, 0, "read error in the data");

  for (std::size_t i = 0; i < stored.size(); ++i) {
    if (std::isfinite(stored[i])) continue;
    const std::size_t channel = i / MerlTable::kBinsPerChannel, bin = i % MerlTable::kBinsPerChannel;
    const std::size_t phiDiff = bin % MerlTable::kPhiDiffBins;
    const std::size_t thetaDiff = bin / MerlTable::kPhiDiffBins % MerlTable::kThetaDiffBins;
    const std::size_t thetaHalf = bin / (std::size_t(MerlTable::kPhiDiffBins) * MerlTable::kThetaDiffBins);
    throw malformed(file, 0,
                    "non-finite number (NaN or infinity) at byte " +
                        std::to_string(kMerlHeaderBytes + i * sizeof(double)) + " (channel " + "RGB"[channel] +
                        ", theta_half bin " + std::to_string(thetaHalf) + ", theta_diff bin " +
                        std::to_string(thetaDiff) + ", phi_diff bin " + std::to_string(phiDiff) + ")");
  }
  return MerlTable(std::move(stored), file);
}

MeasuredTable readMeasuredTable(const std::filesystem::path& path, TableFormat format) {
  const TableFormat actual = format == TableFormat::Auto ? detectTableFormat(path) : format;
  switch (actual) {
    case TableFormat::Astm:
      return readAstm(path);
    case TableFormat::Pbrt:
      return readPbrt(path);
    case TableFormat::Mat:
      return readMat(path);
    case TableFormat::Merl:
      if (format == TableFormat::Auto)
        throw malformed(path.string(), 0,
                        "is a MERL .binary (a dense table, not a list of samples): read it with readMerl");
      throw Error(Error::Kind::InvalidArgument, "readMeasuredTable: MERL tables are dense; use readMerl");
    case TableFormat::Auto:
      break;
  }
  throw Error(Error::Kind::InvalidArgument, "readMeasuredTable: unknown format");
}

}  // namespace brdfbake
