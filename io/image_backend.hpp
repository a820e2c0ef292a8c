#pragma once
// The OpenImageIO side of image_io.cpp, behind a table of functions.
//
// OpenImageIO links about 200 shared libraries; loading and relocating them costs every process
// about 0.2 s before main. So when libbrdfbake_io is a shared library this code is a separate
// module, brdfbake_image_oiio (image_oiio.cpp), that imageBackend() loads with dlopen on first use:
// a process that reads and writes no image never loads OpenImageIO. A static libbrdfbake_io
// links image_oiio.cpp and OpenImageIO directly (BRDFBAKE_IMAGE_MODULE undefined).
//
// The module knows OpenImageIO and nothing else of brdfbake: it never throws, and returns each
// failure as text ("cannot read image: <OpenImageIO's message>") that image_io.cpp prefixes with the
// file and throws as Error(Io). Every check and every policy (formats, sRGB, alpha, sidecars,
// atomic outputs, size limits) stays in image_io.cpp. Both sides are built together, by the same
// compiler and standard library, so the table passes C++ types; the loader still refuses a module
// of another interface or brdfbake version.

#include <string>

namespace brdfbake::image_backend {

/// Raised whenever a struct or a function of the table changes.
inline constexpr int kInterfaceVersion = 2;

/// Float samples, row-major from the top row, channels interleaved.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  const float* data = nullptr;
};

/// How writeImage stores `Pixels` (the format follows the path's extension).
struct WriteSettings {
  bool eightBitSrgb = false;  ///< 8-bit samples tagged sRGB (PNG; data already encoded); else float
  bool zip = false;           ///< OpenEXR zip compression
  std::string metadata;       ///< the "brdfbake:metadata" attribute; empty for none
};

/// What a write did: `ok`, else `error` (and `systemError`, the errno of a failed write, 0 for
/// other failures). `bytes`: the file's length as written.
struct WriteResult {
  bool ok = false;
  int systemError = 0;
  std::string error;
  unsigned long long bytes = 0;
};

/// What openImage found, for the requested MIP level of the first subimage.
struct Header {
  int width = 0, height = 0, channels = 0;
  int tileHeight = 0;      ///< rows per tile of a tiled file; 0 for scanlines
  int alphaChannel = -1;   ///< as the file says; -1 when it names none
  bool srgb = false;       ///< integer samples tagged sRGB
  std::string metadata;    ///< level 0's "brdfbake:metadata" attribute, empty if absent
  bool levelFound = true;  ///< false: the file has no such MIP level (then only `levels` is set)
  int levels = 1;          ///< the file's MIP level count, counted (up to 64) only when !levelFound
};

struct Reader;  ///< an open image file

struct Functions {
  int interfaceVersion;         ///< kInterfaceVersion of the module
  const char* brdfbakeVersion;  ///< the brdfbake version the module was built with
  /// Writes one image in the format of `path`'s extension into the open, empty file `fd` (which the
  /// caller closes), every write checked (an OpenImageIO writer that ignores a failed write still
  /// fails here).
  WriteResult (*writeImage)(int fd, const char* path, const Pixels& pixels, const WriteSettings& settings);
  /// Writes `count` RGBA levels as one tiled (64 x 64), MIP-mapped, zip-compressed OpenEXR into `fd`.
  WriteResult (*writeTiledMipChain)(int fd, const char* path, const Pixels* levels, int count,
                                    const std::string& metadata, const std::string& wrapModes);
  /// The number of MIP levels of the first subimage (up to 64), read with the reader `format`;
  /// -1 and `error` on failure.
  int (*mipLevelCount)(const char* path, const char* format, std::string& error);
  /// Opens the file with OpenImageIO's reader `format` only ("openexr", "hdr", "png", "tiff") at
  /// `mipLevel` and fills `header`; nullptr and `error` on failure.
  Reader* (*openImage)(const char* path, const char* format, int mipLevel, Header& header, std::string& error);
  /// Reads rows [yBegin, yEnd) of the open level (for a tiled file yBegin a multiple of the tile
  /// height, yEnd too or the height) as float, width x rows x channels, into `data`.
  bool (*readRows)(Reader* reader, int yBegin, int yEnd, float* data, std::string& error);
  void (*closeImage)(Reader* reader);
};

/// The table: loaded from the module on first use (shared builds; throws Error(Io) naming the module
/// path and the loader's message when it cannot be loaded), or linked in (static builds).
const Functions& imageBackend();

}  // namespace brdfbake::image_backend

/// The module's one entry point (the one symbol it exports).
extern "C" __attribute__((visibility("default"))) const brdfbake::image_backend::Functions*
brdfbake_image_oiio_functions();
