#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/json_text.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/maps/texture.hpp>

#include <algorithm>
#include <fstream>
#include <memory>

#include "image_backend.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

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
        throw Error(Error::Kind::Numerical, path.string() + ": refusing to write a non-finite value at texel (" +
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

// A header can claim any size. Before allocating, the pixel count must be one the file's bytes
// can encode (no codec we read packs more than kMaxSamplesPerByte samples into a byte; deflate's
// limit is about 1032 bytes per byte) and the buffers must fit the memory budget.
constexpr double kMaxSamplesPerByte = 4096.0;
void checkDecodedSize(int width, int height, int channels, std::uintmax_t fileBytes, const fs::path& path) {
  const double samples = static_cast<double>(width) * height * channels;
  const std::string size = std::to_string(width) + " x " + std::to_string(height) + " x " + std::to_string(channels);
  if (samples > kMaxSamplesPerByte * static_cast<double>(fileBytes) + 65536.0) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": header says " + size + " samples, more than a " +
                                               std::to_string(fileBytes) +
                                               "-byte file can hold (truncated or corrupt)");
  }
  requireWithinMemoryBudget(samples * sizeof(float) + static_cast<double>(width) * height * 4 * sizeof(float),
                            path.string() + ": reading a " + size + " image");
}

}  // namespace

void requireFinite(const Image& image, const std::string& label) {
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgba v = image.at(x, y);
      if (allFinite(v)) continue;
      const bool nan = v.isNaN().any();
      throw Error(Error::Kind::InvalidInput, label + ": texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                 ") is " + (nan ? "NaN" : "infinite") +
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
  throw Error(Error::Kind::InvalidArgument, path.string() + ": unsupported image extension '" + ext +
                                                "' (use .exr, .hdr, .tif, .tiff, .png, .ktx2, .ktx or .dds)");
}

bool isTextureContainer(ImageFormat format) {
  return format == ImageFormat::Ktx2 || format == ImageFormat::Ktx1 || format == ImageFormat::Dds;
}

namespace {
// True if the file is read as a texture container: its first bytes say so, or its extension does
// (then the container reader names what is wrong).
bool readsAsTexture(const fs::path& path) {
  if (textureContainerFor(path)) return true;
  std::ifstream in(path, std::ios::binary);
  char first[12] = {};
  in.read(first, sizeof first);
  return textureContainerOf(std::string_view(first, static_cast<std::size_t>(in.gcount()))).has_value();
}
}  // namespace

fs::path metadataSidecarPath(const fs::path& path) { return path.string() + ".json"; }

WriteReport writeImage(const Image& image, const fs::path& path, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  path.string() + ": output would overwrite an input; choose another output path");
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
  std::string error;
  if (!backend.writeImage(output.temporaryPath().c_str(), {image.width(), image.height(), channels, pixels.data()},
                          settings, error)) {
    throw Error(Error::Kind::Io, path.string() + ": " + error);
  }
  // Formats that drop custom attributes get a sidecar; written before the image so the pair appears together.
  const fs::path sidecar = metadataSidecarPath(path);
  if (!metadata.empty() && backend.readMetadata(output.temporaryPath().c_str()) != metadata) {
    writeFileAtomically(sidecar, image.metadata.dump(2) + "\n");
    report.sidecar = true;
    report.notes.push_back("format drops custom metadata: written to " + sidecar.string());
  } else {
    std::error_code ec;
    fs::remove(sidecar, ec);  // a stale sidecar from an earlier write would contradict the file
  }
  output.commit();
  return report;
}

int imageMipLevelCount(const fs::path& path) {
  requireInputFile(path, "image");
  if (readsAsTexture(path)) return readTextureHeaderOf(path).levels;
  std::string error;
  const int levels = imageBackend().mipLevelCount(path.c_str(), error);
  if (levels < 0) throw Error(Error::Kind::Io, path.string() + ": " + error);
  return levels;
}

WriteReport writeTiledMipChain(const std::vector<Image>& levels, const nlohmann::json& metadata, const fs::path& path,
                               const std::string& wrapModes, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  path.string() + ": output would overwrite an input; choose another output path");
    }
  }
  if (imageFormatFor(path) != ImageFormat::OpenExr) {
    throw Error(Error::Kind::InvalidArgument, path.string() + ": a tiled MIP-mapped file must be OpenEXR (.exr)");
  }
  require(!levels.empty(), "writeTiledMipChain: no levels");
  // OpenEXR's MIPMAP_LEVELS with ROUND_DOWN: level k is max(1, floor(w / 2^k)) x max(1, floor(h / 2^k)),
  // down to 1 x 1.
  const int w = levels[0].width(), h = levels[0].height();
  int expected = 1;
  while ((w >> expected) > 0 || (h >> expected) > 0) ++expected;
  if (static_cast<int>(levels.size()) != expected) {
    throw Error(Error::Kind::InvalidArgument, path.string() + ": a " + std::to_string(w) + " x " + std::to_string(h) +
                                                  " MIP-mapped OpenEXR has " + std::to_string(expected) +
                                                  " levels, got " + std::to_string(levels.size()));
  }
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const int lw = std::max(1, w >> k), lh = std::max(1, h >> k);
    if (levels[k].width() != lw || levels[k].height() != lh) {
      throw Error(Error::Kind::InvalidArgument, path.string() + ": MIP level " + std::to_string(k) + " is " +
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
  std::string error;
  if (!backend.writeTiledMipChain(output.temporaryPath().c_str(), pixels.data(), static_cast<int>(pixels.size()), text,
                                  wrapModes, error)) {
    throw Error(Error::Kind::Io, path.string() + ": " + error);
  }
  std::error_code ec;
  fs::remove(metadataSidecarPath(path), ec);  // OpenEXR keeps the metadata; a stale sidecar would contradict it
  output.commit();
  return {};
}

Image readImage(const fs::path& path, int mipLevel) {
  const std::uintmax_t fileBytes = requireInputFile(path, "image");
  require(mipLevel >= 0, "readImage: MIP level must be >= 0");
  if (readsAsTexture(path)) {
    Texture texture = readTexture(path, mipLevel);
    Image image = texture.isCube() ? crossOfCubeFaces(texture.levels[0]) : std::move(texture.levels[0][0]);
    image.metadata = std::move(texture.metadata);
    return image;
  }
  const image_backend::Functions& backend = imageBackend();
  image_backend::Header header;
  std::string error;
  const OpenImage in(backend.openImage(path.c_str(), mipLevel, header, error));
  if (!in) throw Error(Error::Kind::Io, path.string() + ": " + error);
  std::string metadata = header.metadata;
  if (!header.levelFound) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": has " + std::to_string(header.levels) + " MIP level" +
                                               (header.levels == 1 ? "" : "s") + ", no level " +
                                               std::to_string(mipLevel));
  }
  const int width = header.width, height = header.height, channels = header.channels;
  if (width < 1 || height < 1 || channels < 1) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": image has no pixels");
  }
  checkDecodedSize(width, height, channels, fileBytes, path);
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * channels);
  if (!backend.readPixels(in.get(), pixels.data(), error)) throw Error(Error::Kind::Io, path.string() + ": " + error);
  const bool srgb = header.srgb;
  const int alpha =
      header.alphaChannel >= 0 ? header.alphaChannel : (channels == 2 || channels >= 4 ? channels - 1 : -1);
  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float* p = &pixels[(static_cast<std::size_t>(y) * width + x) * channels];
      Rgba v;
      const bool gray = channels < 3;
      for (int c = 0; c < 3; ++c) {
        const float raw = gray ? p[0] : p[c];
        v[c] = srgb ? srgbToLinear(raw) : raw;
      }
      v[3] = alpha >= 0 ? p[alpha] : 1.0f;
      image.set(x, y, v);
    }
  }
  std::string metadataSource = path.string() + " (brdfbake metadata)";
  const fs::path sidecar = metadataSidecarPath(path);
  std::error_code ec;
  if (metadata.empty() && fs::is_regular_file(sidecar, ec)) {
    metadata = readTextFile(sidecar, "metadata sidecar");
    metadataSource = sidecar.string();
  }
  if (!metadata.empty()) image.metadata = parseJsonText(metadata, metadataSource);
  return image;
}

}  // namespace brdfbake
