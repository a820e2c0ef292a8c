#pragma once
/// @file
/// Reading and writing images: OpenEXR, Radiance HDR, TIFF and PNG through OpenImageIO; KTX2, KTX1
/// and DDS through brdfbake's own texture containers (texture.hpp).

#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// Image file formats brdfbake writes, chosen by the output's extension.
enum class ImageFormat { OpenExr, RadianceHdr, Tiff, Png, Ktx2, Ktx1, Dds };

/// Format for a path's extension (.exr, .hdr, .tif/.tiff, .png, .ktx2, .ktx, .dds); throws
/// Error(InvalidArgument).
ImageFormat imageFormatFor(const std::filesystem::path& path);
/// True for the texture containers KTX2, KTX1 and DDS (texture.hpp).
bool isTextureContainer(ImageFormat format);

struct WriteOptions {
  /// Paths that must not be overwritten (the inputs of the computation).
  std::vector<std::filesystem::path> inputs;
  /// How KTX2, KTX1 and DDS outputs store texels (Rgba16Float if unset); ignored by other formats
  /// (containerProblem, map_file.hpp, reports a format given for them).
  std::optional<TexelFormat> texelFormat;
};

/// What writeImage did, for reports.
struct WriteReport {
  std::vector<std::string> notes;  ///< e.g. "8-bit PNG: sRGB transfer curve, values clamped to [0, 1]"
  bool sidecar = false;            ///< metadata went to PATH.json because the format cannot hold it
};

/// Writes `image` atomically: to a temporary file in the same folder, then renamed over `path`,
/// so a failure never leaves a half-written file. OpenEXR and TIFF are written as float RGBA,
/// Radiance HDR as RGB (alpha dropped, noted), PNG as 8-bit sRGB with clamping (noted). Image
/// metadata is stored in the file's "brdfbake:metadata" attribute, verified by reading it back, or
/// in a sidecar PATH.json where the format drops it. KTX2, KTX1 and DDS: one level in
/// `options.texelFormat` (writeTexture); a cube cross (isCubeCross) becomes a cube texture of six
/// faces, anything else a 2-D texture. Throws Error(Io) on failure and
/// Error(InvalidArgument) if `path` is one of `options.inputs`, or holds NaN/Inf.
WriteReport writeImage(const Image& image, const std::filesystem::path& path, const WriteOptions& options = {});

/// PATH.json: where writeImage puts (or removes) the metadata of `path` when its format drops
/// custom attributes, and where readImage looks for it.
std::filesystem::path metadataSidecarPath(const std::filesystem::path& path);
/// The metadata in `path`'s sidecar (metadataSidecarPath) when it is a regular file, else null. A
/// sidecar over kMaxJsonBytes is refused before it is read (Error(Resource) naming it), bad JSON
/// (Error(InvalidInput)) named with line and column.
nlohmann::json readMetadataSidecar(const std::filesystem::path& path);

/// Reads any format OpenImageIO reads, and KTX2, KTX1 and DDS (by their identifiers, readTexture;
/// a cube texture comes back as the cube cross, crossOfCubeFaces), as float RGBA (alpha 1 if
/// absent; gray expanded to RGB), with its brdfbake metadata if present. Throws Error(Io) naming
/// the file. `mipLevel` > 0 reads that level of a MIP-mapped file (writeTiledMipChain, maketx, a
/// texture's levels); Error(InvalidInput) if it has fewer levels.
Image readImage(const std::filesystem::path& path, int mipLevel = 0);

/// The number of MIP levels in the file's first subimage (1 for an ordinary image).
int imageMipLevelCount(const std::filesystem::path& path);

/// Writes `levels` (level 0 first, each half the size of the one before, rounding down, as
/// OpenEXR's ROUND_DOWN MIP-map mode lays them out) as one tiled, MIP-mapped OpenEXR, as
/// OpenImageIO's make_texture / maketx write them: 64 x 64 tiles, float RGBA, zip compression,
/// "textureformat" "Plain Texture", wrap modes `wrapModes` (e.g. "clamp,clamp"), so OIIO's
/// TextureSystem and ImageInput read every level. `metadata` (the map's, for level 0) goes to the
/// file's "brdfbake:metadata" attribute. Written atomically (AtomicOutput). Throws
/// Error(InvalidArgument) for a path other than .exr, levels of the wrong sizes, non-finite
/// values or a path in options.inputs; Error(Io) on failure.
WriteReport writeTiledMipChain(const std::vector<Image>& levels, const nlohmann::json& metadata,
                               const std::filesystem::path& path, const std::string& wrapModes,
                               const WriteOptions& options = {});

/// Throws Error(InvalidInput) "<label>: texel (x, y) is NaN|infinite" for the first non-finite
/// value. Zero and negative values are accepted (negative radiance is kept as stored).
void requireFinite(const Image& image, const std::string& label);

}  // namespace brdfbake
