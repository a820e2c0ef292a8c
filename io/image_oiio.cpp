// The OpenImageIO side of image I/O (image_backend.hpp): the module brdfbake_image_oiio in shared
// builds, part of libbrdfbake_io in static ones. No function lets an exception out.
#include "image_backend.hpp"

#include <brdfbake/core/version.hpp>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
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

// OpenImageIO's writers reach the file only through this proxy, which writes with pwrite and keeps
// the first failure. Some writers ignore a failed write (the PNG writer kept a 24 KB file of 101 KB
// on a full disk and reported success); here every failure is seen.
class CheckedFileWriter final : public OIIO::Filesystem::IOProxy {
 public:
  CheckedFileWriter(int fd, const char* path) : IOProxy(path, Write), fd_(fd) {}
  const char* proxytype() const override { return "brdfbake-checked"; }
  size_t write(const void* buf, size_t size) override {
    const size_t written = pwrite(buf, size, m_pos);
    m_pos += static_cast<int64_t>(written);
    return written;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    if (failure_ != 0) return 0;
    const char* bytes = static_cast<const char*>(buf);
    size_t done = 0;
    while (done < size) {
      const ssize_t n = ::pwrite(fd_, bytes + done, size - done, static_cast<off_t>(offset) + static_cast<off_t>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        failure_ = n < 0 ? errno : ENOSPC;
        break;
      }
      done += static_cast<size_t>(n);
    }
    end_ = std::max(end_, static_cast<unsigned long long>(offset) + done);
    return done;
  }
  size_t read(void* buf, size_t size) override {
    const size_t got = pread(buf, size, m_pos);
    m_pos += static_cast<int64_t>(got);
    return got;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    const ssize_t n = ::pread(fd_, buf, size, static_cast<off_t>(offset));
    return n > 0 ? static_cast<size_t>(n) : 0;
  }
  size_t size() const override { return static_cast<size_t>(end_); }
  int failure() const { return failure_; }
  unsigned long long end() const { return end_; }

 private:
  int fd_;
  int failure_ = 0;
  unsigned long long end_ = 0;
};

// The result of a write through `proxy`: a failed write wins over what OpenImageIO said.
WriteResult finish(const CheckedFileWriter& proxy, bool ok, const std::string& error) {
  WriteResult result;
  result.bytes = proxy.end();
  if (proxy.failure() != 0) {
    result.systemError = proxy.failure();
    result.error = std::strerror(proxy.failure());
  } else if (!ok) {
    result.error = error.empty() ? "the image writer failed" : error;
  } else {
    result.ok = true;
  }
  return result;
}

WriteResult writeImage(int fd, const char* path, const Pixels& pixels, const WriteSettings& settings) {
  CheckedFileWriter proxy(fd, path);
  std::string error;
  const bool ok = guarded(error, false, [&] {
    OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels,
                         settings.eightBitSrgb ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (pixels.channels == 4) spec.alpha_channel = 3;
    if (!settings.metadata.empty()) spec.attribute(kMetadataAttribute, settings.metadata);
    if (settings.zip) spec.attribute("compression", "zip");
    // Colours are not premultiplied by alpha (alpha is the texel's coverage of the domain).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (settings.eightBitSrgb) spec.attribute("oiio:ColorSpace", "sRGB");
    OIIO::Filesystem::IOProxy* io = &proxy;
    spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &io);  // the attribute holds the pointer
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      error = "no image writer: " + OIIO::geterror();
      return false;
    }
    out->set_ioproxy(&proxy);
    const bool written = out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data);
    const bool closed = out->close();
    if (!written || !closed) error = "cannot write: " + out->geterror();
    return written && closed;
  });
  return finish(proxy, ok, error);
}

// One MIP level of a tiled file, written with one write_tiles call. Not write_image: OpenImageIO
// 2.4's write_image goes on calling write_tiles for each row of tiles after one failed, and after
// a failed write OpenEXR's TiledOutputFile::writeTiles leaves a tile buffer's semaphore taken, so
// the next call waited on it for ever (`prefilter --mips --tiled` hung on a full disk).
bool writeLevel(OIIO::ImageOutput& out, const Pixels& level) {
  return out.write_tiles(0, level.width, 0, level.height, 0, 1, OIIO::TypeDesc::FLOAT, level.data);
}

WriteResult writeTiledMipChain(int fd, const char* path, const Pixels* levels, int count, const std::string& metadata,
                               const std::string& wrapModes) {
  CheckedFileWriter proxy(fd, path);
  std::string error;
  const bool ok = guarded(error, false, [&] {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      error = "no image writer: " + OIIO::geterror();
      return false;
    }
    out->set_ioproxy(&proxy);
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
      OIIO::Filesystem::IOProxy* io = &proxy;
      spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &io);
      if (k == 0 && !metadata.empty()) spec.attribute(kMetadataAttribute, metadata);
      const auto mode = k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
      if (!out->open(path, spec, mode) || !writeLevel(*out, levels[k]) || proxy.failure() != 0) {
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
  return finish(proxy, ok, error);
}

// Opens `path` with the reader `format` only: OpenImageIO's ImageInput::open would try every
// reader it has when the first refuses the file.
std::unique_ptr<OIIO::ImageInput> openWith(const char* path, const char* format, const OIIO::ImageSpec* config,
                                           std::string& error) {
  auto in = OIIO::ImageInput::create(format, /*do_open=*/false);
  if (!in) {
    error = "cannot read image: no " + std::string(format) + " reader: " + OIIO::geterror();
    return nullptr;
  }
  OIIO::ImageSpec spec;
  if (!(config ? in->open(path, spec, *config) : in->open(path, spec))) {
    error = "cannot read image: " + in->geterror();
    return nullptr;
  }
  return in;
}

int mipLevelCount(const char* path, const char* format, std::string& error) {
  return guarded(error, -1, [&] {
    auto in = openWith(path, format, nullptr, error);
    if (!in) return -1;
    return countLevels(*in);
  });
}

Reader* openImage(const char* path, const char* format, int mipLevel, Header& header, std::string& error) {
  return guarded(error, static_cast<Reader*>(nullptr), [&]() -> Reader* {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep colours as stored, never premultiplied
    auto reader = std::make_unique<Reader>();
    reader->input = openWith(path, format, &config, error);
    if (!reader->input) return nullptr;
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
    header.tileHeight = spec.tile_width > 0 ? spec.tile_height : 0;
    header.alphaChannel = spec.alpha_channel;
    header.srgb = spec.format.basetype != OIIO::TypeDesc::FLOAT && spec.format.basetype != OIIO::TypeDesc::HALF &&
                  spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
    return reader.release();
  });
}

bool readRows(Reader* reader, int yBegin, int yEnd, float* data, std::string& error) {
  return guarded(error, false, [&] {
    OIIO::ImageInput& in = *reader->input;
    const OIIO::ImageSpec& spec = in.spec();
    const int y0 = spec.y + yBegin, y1 = spec.y + yEnd;
    const bool ok =
        spec.tile_width > 0
            ? in.read_tiles(0, reader->mipLevel, spec.x, spec.x + spec.width, y0, y1, spec.z,
                            spec.z + std::max(1, spec.depth), 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data)
            : in.read_scanlines(0, reader->mipLevel, y0, y1, spec.z, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data);
    if (!ok) error = "cannot read pixels: " + in.geterror();
    return ok;
  });
}

void closeImage(Reader* reader) { delete reader; }

constexpr Functions kFunctions{
    kInterfaceVersion, BRDFBAKE_VERSION_STRING, writeImage, writeTiledMipChain, mipLevelCount, openImage, readRows,
    closeImage};

}  // namespace
}  // namespace brdfbake::image_backend

extern "C" const brdfbake::image_backend::Functions* brdfbake_image_oiio_functions() {
  return &brdfbake::image_backend::kFunctions;
}
