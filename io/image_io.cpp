#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/json_text.hpp>
#include <brdfbake/io/texture.hpp>

#include <brdfbake/core/printable.hpp>

#include <algorithm>
#include <fstream>
#include <memory>

#include "image_backend.hpp"
#include "image_header.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

std::string named(const fs::path& path) { return printable(path.string()); }

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

void checkFinite(const Image& image, const fs::path& path) {
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      if (!allFinite(image.at(x, y))) {
        throw Error(Error::Kind::Numerical, named(path) + ": refusing to write a non-finite value at texel (" +
                                                std::to_string(x) + ", " + std::to_string(y) + ")");
      }
    }
  }
}

using image_backend::imageBackend;

// An image open through the backend, closed at scope exit.
struct ReaderCloser {
  void operator()(image_backend::Reader* reader) const { imageBackend().closeImage(reader); }
};
using OpenImage = std::unique_ptr<image_backend::Reader, ReaderCloser>;

const char* readerName(image_header::Format format) {
  switch (format) {
    case image_header::Format::OpenExr:
      return "openexr";
    case image_header::Format::RadianceHdr:
      return "hdr";
    case image_header::Format::Png:
      return "png";
    case image_header::Format::Tiff:
      return "tiff";
  }
  return "openexr";
}

image_header::Format headerFormat(ImageFormat format) {
  switch (format) {
    case ImageFormat::OpenExr:
      return image_header::Format::OpenExr;
    case ImageFormat::RadianceHdr:
      return image_header::Format::RadianceHdr;
    case ImageFormat::Png:
      return image_header::Format::Png;
    case ImageFormat::Tiff:
      return image_header::Format::Tiff;
    case ImageFormat::Ktx2:
    case ImageFormat::Ktx1:
    case ImageFormat::Dds:
      break;  // read by maps/texture.cpp, never through the image backend
  }
  return image_header::Format::OpenExr;
}

// A failed write through the backend, named by the output (never its temporary).
Error writeError(const AtomicOutput& output, const image_backend::WriteResult& result) {
  if (result.systemError != 0) return output.writeFailed(result.systemError);
  return Error(Error::Kind::Io, named(output.target()) + ": " + printable(result.error, 1000));
}

// The last `count` bytes of `file` (fewer if it is shorter).
std::string tailOf(const fs::path& file, std::uintmax_t size, std::size_t count) {
  std::ifstream in(file, std::ios::binary);
  const std::uintmax_t start = size > count ? size - count : 0;
  in.seekg(static_cast<std::streamoff>(start));
  std::string tail(static_cast<std::size_t>(size - start), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  return in ? tail : std::string();
}

// Reads the finished temporary of `output` back, cheaply: its length is what was written, its header
// opens with the size and channels written, and a PNG ends with its IEND chunk. Returns the metadata
// attribute the file kept (empty if the format drops it).
std::string verifyWritten(const AtomicOutput& output, ImageFormat format, const image_backend::Pixels& written,
                          unsigned long long bytes) {
  const std::string shown = named(output.target());
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(output.temporaryPath(), ec);
  if (ec || size != bytes || size == 0) {
    throw Error(Error::Kind::Io, shown + ": the file written has " + std::to_string(ec ? 0 : size) +
                                     " bytes, not the " + std::to_string(bytes) + " written (is the disk full?)");
  }
  if (format == ImageFormat::Png && tailOf(output.temporaryPath(), size, 8) != std::string("IEND\xae\x42\x60\x82", 8)) {
    throw Error(Error::Kind::Io, shown + ": the PNG written does not end with its IEND chunk");
  }
  image_backend::Header header;
  std::string error;
  const image_backend::Functions& backend = imageBackend();
  image_backend::Reader* reader =
      backend.openImage(output.temporaryPath().c_str(), readerName(headerFormat(format)), 0, header, error);
  if (reader == nullptr) throw Error(Error::Kind::Io, shown + ": the file written does not open: " + error);
  backend.closeImage(reader);
  if (header.width != written.width || header.height != written.height || header.channels != written.channels) {
    throw Error(Error::Kind::Io, shown + ": the file written reads back as " + std::to_string(header.width) + " x " +
                                     std::to_string(header.height) + " x " + std::to_string(header.channels) +
                                     ", not as written");
  }
  return header.metadata;
}

void removeStaleSidecar(const fs::path& path) {
  const fs::path sidecar = metadataSidecarPath(path);
  std::error_code ec;
  if (fs::is_regular_file(fs::symlink_status(sidecar, ec))) fs::remove(sidecar, ec);
}

// The open level's pixels as float RGBA, decoded a strip of rows at a time (about 16 MiB of samples),
// so the only full-size buffer is the image itself, which must fit the memory budget.
Image readPixelsInStrips(image_backend::Reader* reader, const image_backend::Header& header, const fs::path& path) {
  const int width = header.width, height = header.height, channels = header.channels;
  const double rowBytes = static_cast<double>(width) * channels * sizeof(float);
  int rows = static_cast<int>(std::clamp(16.0 * (1 << 20) / rowBytes, 1.0, static_cast<double>(height)));
  if (header.tileHeight > 0) rows = std::max(header.tileHeight, rows / header.tileHeight * header.tileHeight);
  requireWithinMemoryBudget(
      static_cast<double>(width) * height * 4 * sizeof(float) + rowBytes * rows,
      named(path) + ": reading a " + std::to_string(width) + " x " + std::to_string(height) + " image");
  const bool srgb = header.srgb;
  const int alpha =
      header.alphaChannel >= 0 ? header.alphaChannel : (channels == 2 || channels >= 4 ? channels - 1 : -1);
  Image image(width, height);
  std::vector<float> strip(static_cast<std::size_t>(width) * channels * static_cast<std::size_t>(rows));
  std::string error;
  for (int y0 = 0; y0 < height; y0 += rows) {
    const int y1 = std::min(height, y0 + rows);
    if (!imageBackend().readRows(reader, y0, y1, strip.data(), error)) {
      throw Error(Error::Kind::Io, named(path) + ": " + printable(error, 1000));
    }
    for (int y = y0; y < y1; ++y) {
      for (int x = 0; x < width; ++x) {
        const float* p = &strip[(static_cast<std::size_t>(y - y0) * width + x) * channels];
        Rgba v;
        for (int c = 0; c < 3; ++c) {
          const float raw = channels < 3 ? p[0] : p[c];
          v[c] = srgb ? srgbToLinear(raw) : raw;
        }
        v[3] = alpha >= 0 ? p[alpha] : 1.0f;
        image.set(x, y, v);
      }
    }
  }
  return image;
}

}  // namespace

void requireFinite(const Image& image, const std::string& label) {
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgba v = image.at(x, y);
      if (allFinite(v)) continue;
      const bool nan = v.isNaN().any();
      throw Error(Error::Kind::InvalidInput, printable(label) + ": texel (" + std::to_string(x) + ", " +
                                                 std::to_string(y) + ") is " + (nan ? "NaN" : "infinite") +
                                                 "; brdfbake needs finite values (repair or clamp the image first)");
    }
  }
}

ImageFormat imageFormatFor(const fs::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".exr") return ImageFormat::OpenExr;
  if (ext == ".hdr") return ImageFormat::RadianceHdr;
  if (ext == ".tif" || ext == ".tiff") return ImageFormat::Tiff;
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".ktx2") return ImageFormat::Ktx2;
  if (ext == ".ktx") return ImageFormat::Ktx1;
  if (ext == ".dds") return ImageFormat::Dds;
  throw Error(Error::Kind::InvalidArgument, named(path) + ": unsupported image extension '" + printable(ext, 40) +
                                                "' (use .exr, .hdr, .tif, .tiff, .png, .ktx2, .ktx or .dds)");
}

bool isTextureContainer(ImageFormat format) {
  return format == ImageFormat::Ktx2 || format == ImageFormat::Ktx1 || format == ImageFormat::Dds;
}

namespace {
// True if the file is read as a texture container: its first bytes say so, or its extension does
// (then the container reader names what is wrong).
bool readsAsTexture(const InputFile& file) {
  return textureContainerFor(file.path()) || textureContainerOf(file.read(0, 12)).has_value();
}

// The backend's message, naming the file by its path rather than the name it was opened by.
std::string backendError(const InputFile& file, std::string error) {
  const std::string opened = file.openName().string();
  for (std::size_t at = error.find(opened); at != std::string::npos; at = error.find(opened, at))
    error.replace(at, opened.size(), file.path().string());
  return named(file.path()) + ": " + printable(error, 1000);
}
}  // namespace

fs::path metadataSidecarPath(const fs::path& path) { return path.string() + ".json"; }

nlohmann::json readMetadataSidecar(const fs::path& path) {
  const fs::path sidecar = metadataSidecarPath(path);
  std::error_code ec;
  if (!fs::is_regular_file(sidecar, ec)) return nullptr;
  return parseJsonText(readTextFile(sidecar, "metadata sidecar", kMaxJsonBytes), sidecar.string());
}

WriteReport writeImage(const Image& image, const fs::path& path, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  named(path) + ": output would overwrite an input; choose another output path");
    }
  }
  const ImageFormat format = imageFormatFor(path);
  checkFinite(image, path);
  if (isTextureContainer(format)) {
    Texture texture;
    if (image.metadata.is_object()) texture.metadata = image.metadata;
    if (isCubeCross(image)) {
      texture.levels = {cubeFacesOfCross(image)};
    } else {
      texture.levels = {{image}};
    }
    return writeTexture(texture, path, options);
  }

  WriteReport report;
  const int channels = format == ImageFormat::RadianceHdr ? 3 : 4;
  image_backend::WriteSettings settings;
  settings.eightBitSrgb = format == ImageFormat::Png;
  settings.zip = format == ImageFormat::OpenExr;
  const std::string metadata = image.metadata.empty() ? std::string() : image.metadata.dump();
  settings.metadata = metadata;

  std::vector<float> pixels(static_cast<std::size_t>(image.width()) * image.height() * channels);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const float* src = image.data() + image.index(x, y);
      float* dst = &pixels[(static_cast<std::size_t>(y) * image.width() + x) * channels];
      for (int c = 0; c < channels; ++c) {
        dst[c] = (format == ImageFormat::Png && c < 3) ? linearToSrgb(src[c])
                 : format == ImageFormat::Png          ? std::clamp(src[c], 0.0f, 1.0f)
                                                       : src[c];
      }
    }
  }
  if (format == ImageFormat::Png) {
    report.notes.push_back("8-bit PNG: linear values clamped to [0, 1] and encoded with the sRGB transfer curve");
  }
  if (format == ImageFormat::RadianceHdr)
    report.notes.push_back("Radiance HDR holds RGB only: alpha (coverage) dropped");

  const image_backend::Functions& backend = imageBackend();
  AtomicOutput output(path);
  const image_backend::Pixels written{image.width(), image.height(), channels, pixels.data()};
  const image_backend::WriteResult result = backend.writeImage(output.open(), path.c_str(), written, settings);
  if (!result.ok) throw writeError(output, result);
  output.close();
  const std::string kept = verifyWritten(output, format, written, result.bytes);
  // Formats that drop custom attributes get a sidecar; written before the image so the pair appears together.
  const fs::path sidecar = metadataSidecarPath(path);
  if (!metadata.empty() && kept != metadata) {
    try {
      writeFileAtomically(sidecar, image.metadata.dump(2) + "\n");
    } catch (const Error& e) {
      throw Error(e.kind(), named(path) + ": cannot write its metadata sidecar: " + e.what());
    }
    report.sidecar = true;
    report.notes.push_back("format drops custom metadata: written to " + named(sidecar));
  } else {
    removeStaleSidecar(path);
  }
  output.commit();
  return report;
}

int imageMipLevelCount(const fs::path& path) {
  const InputFile file(path, "image");
  if (readsAsTexture(file)) return readTextureHeaderOf(path).levels;
  const image_header::Claim claim = image_header::checkHeaderOfFile(file);
  std::string error;
  const int levels = imageBackend().mipLevelCount(file.openName().c_str(), readerName(claim.format), error);
  if (levels < 0) throw Error(Error::Kind::Io, backendError(file, std::move(error)));
  return levels;
}

WriteReport writeTiledMipChain(const std::vector<Image>& levels, const nlohmann::json& metadata, const fs::path& path,
                               const std::string& wrapModes, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  named(path) + ": output would overwrite an input; choose another output path");
    }
  }
  if (imageFormatFor(path) != ImageFormat::OpenExr) {
    throw Error(Error::Kind::InvalidArgument, named(path) + ": a tiled MIP-mapped file must be OpenEXR (.exr)");
  }
  require(!levels.empty(), "writeTiledMipChain: no levels");
  // OpenEXR's MIPMAP_LEVELS with ROUND_DOWN: level k is max(1, floor(w / 2^k)) x max(1, floor(h / 2^k)),
  // down to 1 x 1.
  const int w = levels[0].width(), h = levels[0].height();
  int expected = 1;
  while ((w >> expected) > 0 || (h >> expected) > 0) ++expected;
  if (static_cast<int>(levels.size()) != expected) {
    throw Error(Error::Kind::InvalidArgument, named(path) + ": a " + std::to_string(w) + " x " + std::to_string(h) +
                                                  " MIP-mapped OpenEXR has " + std::to_string(expected) +
                                                  " levels, got " + std::to_string(levels.size()));
  }
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const int lw = std::max(1, w >> k), lh = std::max(1, h >> k);
    if (levels[k].width() != lw || levels[k].height() != lh) {
      throw Error(Error::Kind::InvalidArgument, named(path) + ": MIP level " + std::to_string(k) + " is " +
                                                    std::to_string(levels[k].width()) + " x " +
                                                    std::to_string(levels[k].height()) + ", OpenEXR expects " +
                                                    std::to_string(lw) + " x " + std::to_string(lh));
    }
    checkFinite(levels[k], path);
  }
  const std::string text = metadata.empty() ? std::string() : metadata.dump();
  std::vector<image_backend::Pixels> pixels;
  for (const Image& level : levels) pixels.push_back({level.width(), level.height(), 4, level.data()});
  const image_backend::Functions& backend = imageBackend();
  AtomicOutput output(path);
  const image_backend::WriteResult result = backend.writeTiledMipChain(
      output.open(), path.c_str(), pixels.data(), static_cast<int>(pixels.size()), text, wrapModes);
  if (!result.ok) throw writeError(output, result);
  output.close();
  verifyWritten(output, ImageFormat::OpenExr, pixels.front(), result.bytes);
  removeStaleSidecar(path);  // OpenEXR keeps the metadata; a stale sidecar would contradict it
  output.commit();
  return {};
}

Image readImage(const fs::path& path, int mipLevel) {
  require(mipLevel >= 0, "readImage: MIP level must be >= 0");
  // One open file for the header check and the decoder: a replace meanwhile is read as the old file.
  const InputFile file(path, "image");
  if (readsAsTexture(file)) {
    Texture texture = readTexture(path, mipLevel);
    Image image = texture.isCube() ? crossOfCubeFaces(texture.levels[0]) : std::move(texture.levels[0][0]);
    image.metadata = std::move(texture.metadata);
    return image;
  }
  const image_header::Claim claim = image_header::checkHeaderOfFile(file);
  const image_backend::Functions& backend = imageBackend();
  image_backend::Header header;
  std::string error;
  const OpenImage in(backend.openImage(file.openName().c_str(), readerName(claim.format), mipLevel, header, error));
  if (!in) throw Error(Error::Kind::Io, backendError(file, std::move(error)));
  if (!header.levelFound) {
    throw Error(Error::Kind::InvalidInput, named(path) + ": has " + std::to_string(header.levels) + " MIP level" +
                                               (header.levels == 1 ? "" : "s") + ", no level " +
                                               std::to_string(mipLevel));
  }
  const int width = header.width, height = header.height, channels = header.channels;
  if (width < 1 || height < 1 || channels < 1)
    throw Error(Error::Kind::InvalidInput, named(path) + ": image has no pixels");
  if (width > claim.width || height > claim.height) {
    throw Error(Error::Kind::InvalidInput, named(path) + ": the reader found " + std::to_string(width) + " x " +
                                               std::to_string(height) + " pixels, more than its header says");
  }
  Image image = readPixelsInStrips(in.get(), header, path);
  if (!header.metadata.empty()) {
    image.metadata = parseJsonText(header.metadata, path.string() + " (brdfbake metadata)");
  } else if (nlohmann::json sidecar = readMetadataSidecar(path); !sidecar.is_null()) {
    image.metadata = std::move(sidecar);
  }
  return image;
}

}  // namespace brdfbake
