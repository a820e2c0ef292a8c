#include <brdfbake/bake/image_io.hpp>
#include <brdfbake/core/error.hpp>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <fstream>

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

constexpr const char* kMetadataAttribute = "brdfbake:metadata";

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

fs::path temporarySibling(const fs::path& path) {
  static std::atomic<int> counter{0};
  const std::string name = "." + path.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + path.extension().string();
  return path.parent_path() / name;
}

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

std::string readMetadataAttribute(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  return in->spec().get_string_attribute(kMetadataAttribute);
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
  throw Error(Error::Kind::InvalidArgument, path.string() + ": unsupported image extension '" + ext +
                                                "' (use .exr, .hdr, .tif, .tiff or .png)");
}

bool samePath(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

WriteReport writeImage(const Image& image, const fs::path& path, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (samePath(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  path.string() + ": output would overwrite an input; choose another output path");
    }
  }
  const ImageFormat format = imageFormatFor(path);
  checkFinite(image, path);
  if (!path.parent_path().empty()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw Error(Error::Kind::Io, path.parent_path().string() + ": cannot create folder: " + ec.message());
  }

  WriteReport report;
  const int channels = format == ImageFormat::RadianceHdr ? 3 : 4;
  const OIIO::TypeDesc type = format == ImageFormat::Png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(image.width(), image.height(), channels, type);
  if (channels == 4) spec.alpha_channel = 3;
  const std::string metadata = image.metadata.empty() ? std::string() : image.metadata.dump();
  if (!metadata.empty()) spec.attribute(kMetadataAttribute, metadata);
  if (format == ImageFormat::OpenExr) spec.attribute("compression", "zip");
  // Colours are not premultiplied by alpha (alpha is the texel's coverage of the domain).
  spec.attribute("oiio:UnassociatedAlpha", 1);

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
    spec.attribute("oiio:ColorSpace", "sRGB");
    report.notes.push_back("8-bit PNG: linear values clamped to [0, 1] and encoded with the sRGB transfer curve");
  }
  if (format == ImageFormat::RadianceHdr) report.notes.push_back("Radiance HDR holds RGB only: alpha (coverage) dropped");

  const fs::path temporary = temporarySibling(path);
  {
    auto out = OIIO::ImageOutput::create(temporary.string());
    if (!out) throw Error(Error::Kind::Io, path.string() + ": no image writer: " + OIIO::geterror());
    if (!out->open(temporary.string(), spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
      const std::string message = out->geterror();
      std::error_code ec;
      fs::remove(temporary, ec);
      throw Error(Error::Kind::Io, path.string() + ": cannot write: " + message);
    }
  }
  // Formats that drop custom attributes get a sidecar; written before the rename so the pair appears together.
  const fs::path sidecar = path.string() + ".json";
  std::error_code ec;
  if (!metadata.empty() && readMetadataAttribute(temporary) != metadata) {
    const fs::path sidecarTemporary = temporarySibling(sidecar);
    std::ofstream(sidecarTemporary) << image.metadata.dump(2) << "\n";
    fs::rename(sidecarTemporary, sidecar, ec);
    if (ec) {
      fs::remove(temporary, ec);
      throw Error(Error::Kind::Io, sidecar.string() + ": cannot write metadata sidecar: " + ec.message());
    }
    report.sidecar = true;
    report.notes.push_back("format drops custom metadata: written to " + sidecar.string());
  } else {
    fs::remove(sidecar, ec);  // a stale sidecar from an earlier write would contradict the file
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw Error(Error::Kind::Io, path.string() + ": cannot move the finished file into place: " + ec.message());
  }
  return report;
}

Image readImage(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error(Error::Kind::Io, path.string() + ": no such file");
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // keep colours as stored, never premultiplied
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) throw Error(Error::Kind::Io, path.string() + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const int channels = spec.nchannels;
  if (spec.width < 1 || spec.height < 1 || channels < 1) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": image has no pixels");
  }
  std::vector<float> pixels(static_cast<std::size_t>(spec.width) * spec.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    throw Error(Error::Kind::Io, path.string() + ": cannot read pixels: " + in->geterror());
  }
  const bool srgb = spec.format.basetype != OIIO::TypeDesc::FLOAT &&
                    spec.format.basetype != OIIO::TypeDesc::HALF &&
                    spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
  const int alpha = spec.alpha_channel >= 0 ? spec.alpha_channel : (channels == 2 || channels >= 4 ? channels - 1 : -1);
  Image image(spec.width, spec.height);
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
      const float* p = &pixels[(static_cast<std::size_t>(y) * spec.width + x) * channels];
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
  std::string metadata = spec.get_string_attribute(kMetadataAttribute);
  if (metadata.empty()) {
    std::ifstream sidecar(path.string() + ".json");
    if (sidecar) metadata.assign(std::istreambuf_iterator<char>(sidecar), {});
  }
  if (!metadata.empty()) {
    image.metadata = nlohmann::json::parse(metadata, nullptr, /*allow_exceptions=*/false);
    if (image.metadata.is_discarded()) {
      throw Error(Error::Kind::InvalidInput, path.string() + ": brdfbake metadata is not valid JSON");
    }
  }
  return image;
}

}  // namespace brdfbake
