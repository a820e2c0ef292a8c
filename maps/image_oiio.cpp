// The OpenImageIO side of image I/O (image_backend.hpp): the module brdfbake_image_oiio in shared
// builds, part of libbrdfbake_maps in static ones. No function lets an exception out.
#include "image_backend.hpp"

#include <brdfbake/core/version.hpp>

#include <OpenImageIO/imageio.h>

#include <exception>
#include <memory>

namespace brdfbake::image_backend {

struct Reader {
  std::unique_ptr<OIIO::ImageInput> input;
  int mipLevel = 0;
};

namespace {

constexpr const char* kMetadataAttribute = "brdfbake:metadata";

// Runs `body`, turning an exception (bad_alloc, or one from OpenImageIO) into `error`.
template <class T, class Body>
T guarded(std::string& error, T failed, Body body) noexcept {
  try {
    return body();
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown error";
  }
  return failed;
}

int countLevels(OIIO::ImageInput& in) {
  int levels = 1;
  while (levels < 64 && in.seek_subimage(0, levels)) ++levels;
  return levels;
}

bool writeImage(const char* path, const Pixels& pixels, const WriteSettings& settings, std::string& error) {
  return guarded(error, false, [&] {
    OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels,
                         settings.eightBitSrgb ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (pixels.channels == 4) spec.alpha_channel = 3;
    if (!settings.metadata.empty()) spec.attribute(kMetadataAttribute, settings.metadata);
    if (settings.zip) spec.attribute("compression", "zip");
    // Colours are not premultiplied by alpha (alpha is the texel's coverage of the domain).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (settings.eightBitSrgb) spec.attribute("oiio:ColorSpace", "sRGB");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      error = "no image writer: " + OIIO::geterror();
      return false;
    }
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data) || !out->close()) {
      error = "cannot write: " + out->geterror();
      return false;
    }
    return true;
  });
}

bool writeTiledMipChain(const char* path, const Pixels* levels, int count, const std::string& metadata,
                        const std::string& wrapModes, std::string& error) {
  return guarded(error, false, [&] {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      error = "no image writer: " + OIIO::geterror();
      return false;
    }
    for (int k = 0; k < count; ++k) {
      OIIO::ImageSpec spec(levels[k].width, levels[k].height, 4, OIIO::TypeDesc::FLOAT);
      spec.alpha_channel = 3;
      spec.tile_width = spec.tile_height = 64;
      spec.tile_depth = 1;
      spec.attribute("compression", "zip");
      spec.attribute("textureformat", "Plain Texture");
      spec.attribute("wrapmodes", wrapModes);
      spec.attribute("openexr:levelmode", 1);     // MIPMAP_LEVELS
      spec.attribute("openexr:roundingmode", 0);  // ROUND_DOWN
      spec.attribute("oiio:UnassociatedAlpha", 1);
      if (k == 0 && !metadata.empty()) spec.attribute(kMetadataAttribute, metadata);
      const auto mode = k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
      if (!out->open(path, spec, mode) || !out->write_image(OIIO::TypeDesc::FLOAT, levels[k].data)) {
        error = "cannot write MIP level " + std::to_string(k) + ": " + out->geterror();
        return false;
      }
    }
    if (!out->close()) {
      error = "cannot write: " + out->geterror();
      return false;
    }
    return true;
  });
}

std::string readMetadata(const char* path) {
  std::string error;
  return guarded(error, std::string(), [&] {
    auto in = OIIO::ImageInput::open(path);
    return in ? std::string(in->spec().get_string_attribute(kMetadataAttribute)) : std::string();
  });
}

int mipLevelCount(const char* path, std::string& error) {
  return guarded(error, -1, [&] {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      error = "cannot read image: " + OIIO::geterror();
      return -1;
    }
    return countLevels(*in);
  });
}

Reader* openImage(const char* path, int mipLevel, Header& header, std::string& error) {
  return guarded(error, static_cast<Reader*>(nullptr), [&]() -> Reader* {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep colours as stored, never premultiplied
    auto reader = std::make_unique<Reader>();
    reader->input = OIIO::ImageInput::open(path, &config);
    if (!reader->input) {
      error = "cannot read image: " + OIIO::geterror();
      return nullptr;
    }
    OIIO::ImageInput& in = *reader->input;
    header.metadata = in.spec().get_string_attribute(kMetadataAttribute);  // level 0 carries it
    if (mipLevel > 0 && !in.seek_subimage(0, mipLevel)) {
      header.levelFound = false;
      header.levels = countLevels(in);
      return reader.release();
    }
    reader->mipLevel = mipLevel;
    const OIIO::ImageSpec& spec = in.spec();
    header.width = spec.width;
    header.height = spec.height;
    header.channels = spec.nchannels;
    header.alphaChannel = spec.alpha_channel;
    header.srgb = spec.format.basetype != OIIO::TypeDesc::FLOAT && spec.format.basetype != OIIO::TypeDesc::HALF &&
                  spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
    return reader.release();
  });
}

bool readPixels(Reader* reader, float* data, std::string& error) {
  return guarded(error, false, [&] {
    OIIO::ImageInput& in = *reader->input;
    if (!in.read_image(0, reader->mipLevel, 0, in.spec().nchannels, OIIO::TypeDesc::FLOAT, data)) {
      error = "cannot read pixels: " + in.geterror();
      return false;
    }
    return true;
  });
}

void closeImage(Reader* reader) { delete reader; }

constexpr Functions kFunctions{kInterfaceVersion, BRDFBAKE_VERSION_STRING, writeImage, writeTiledMipChain,
                               readMetadata,      mipLevelCount,           openImage,  readPixels,
                               closeImage};

}  // namespace
}  // namespace brdfbake::image_backend

extern "C" const brdfbake::image_backend::Functions* brdfbake_image_oiio_functions() {
  return &brdfbake::image_backend::kFunctions;
}
