#pragma once
/// @file
/// Maps on disk: an image plus the MapInfo that says how to read it.

#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <filesystem>
#include <memory>
#include <optional>

namespace brdfbake {

/// How a cube map is written: one 4N x 3N horizontal cross, or six N x N files
/// STEM_posx.EXT, STEM_negx.EXT, STEM_posy.EXT, STEM_negy.EXT, STEM_posz.EXT, STEM_negz.EXT.
enum class CubeLayout { Cross, Faces };

/// How a mip chain is written: each level a map of its own (level k >= 1 at STEM_mipK.EXT,
/// mipLevelPath), or the whole chain in one file (writeTiledMap): a tiled, MIP-mapped OpenEXR for
/// .exr, as OpenImageIO's make_texture / maketx write textures, or the mip levels of a KTX2, KTX1
/// or DDS texture for .ktx2, .ktx, .dds.
enum class MipLayout { Files, Tiled };

/// What an output will hold, for containerProblem.
struct OutputShape {
  /// The map's parameterization; nullopt for a plain image (a preview, a 1-D table).
  std::optional<ParameterizationKind> parameterization;
  int resolution = 0;       ///< the map's resolution N at level 0 (maps only)
  bool wholeChain = false;  ///< every mip level in this one file (MipLayout::Tiled)
  CubeLayout cubeLayout = CubeLayout::Cross;
  std::optional<TexelFormat> texelFormat;  ///< WriteOptions::texelFormat, if given
};

/// Why `path` cannot hold `shape` ("" if it can), for checks before any work: an unknown
/// extension; a whole chain in a format without mip levels (only .exr, .ktx2, .ktx, .dds hold
/// one) or of a resolution that is not a power of two (each level must halve exactly as the
/// format's levels do); a texel format given for a format other than KTX2, KTX1, DDS, or one the
/// container cannot store (texelFormatProblem).
std::string containerProblem(const std::filesystem::path& path, const OutputShape& shape);

/// containerProblem for a whole chain of a map of `resolution` at `path` (kept for its callers).
std::string tiledMipProblem(const std::filesystem::path& path, int resolution);

/// The values of level `level` in a map's metadata: element `level` of its "level_values" array
/// (e.g. {"roughness": 0.25} for a GGX chain), or an empty object.
nlohmann::json levelValues(const nlohmann::json& metadata, int level);

/// A map read back from disk.
struct MapFile {
  Image image;
  MapInfo info;
  std::unique_ptr<Parameterization> parameterization;
};

/// Reads a map written by writeMap or writeTiledMap: one file, or a cube's six faces
/// (CubeLayout::Faces), named by STEM.EXT (which then need not exist) or by any one face file.
/// A KTX2, KTX1 or DDS cube texture reads as the cross. `mipLevel` > 0 reads that level of the
/// chain: from the file itself if it is MIP-mapped (writeTiledMap: a tiled OpenEXR or a texture's
/// levels), else from STEM_mipK.EXT (mipLevelPath). Throws Error(InvalidInput) if the
/// file has no brdfbake metadata, its size does not match the metadata, a texel is NaN or
/// infinite, or the level does not exist (or lies below the map's 1-texel level); Error(Io) if
/// the file (or a face) is missing.
MapFile readMap(const std::filesystem::path& path, int mipLevel = 0);

/// If `path` names a cube written as six faces (STEM.EXT absent and its six faces present, or a
/// face file whose metadata says "layout": "faces"), the six face paths in OpenGL order; else
/// empty.
std::vector<std::filesystem::path> cubeFaceSet(const std::filesystem::path& path);

/// The six faces (cubeFacePaths order, each square and of one size) as one horizontal cross
/// (unused cells 0), with the metadata of the first face less its "layout" and "face" keys.
/// `mipLevel` as for readImage. Throws Error(InvalidInput) naming the face that does not fit.
Image assembleCubeCross(const std::vector<std::filesystem::path>& faces, int mipLevel = 0);

/// True if `image` carries the metadata writeMap writes (a brdfbake map, not a plain image).
bool hasMapMetadata(const Image& image);

/// readMap's checks on an image already read; `label` names it in messages.
MapFile mapFromImage(Image image, const std::string& label);

/// Wraps a plain environment image (no brdfbake metadata) as a map of the given kind, checking
/// its size (lat-long 2:1, cube cross 4:3, paraboloid 2:1, sphere square) and that every texel
/// is finite.
MapFile adoptImage(Image image, ParameterizationKind kind, const std::string& label);

/// Writes a map with its metadata (image.metadata is replaced by info.toJson()). Returns the
/// files written and the notes of writeImage. A cube map written as .ktx2, .ktx or .dds with
/// CubeLayout::Cross becomes one cube texture (six faces, not a cross); with CubeLayout::Faces six
/// 2-D textures as for any format.
struct MapWriteReport {
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;
};
MapWriteReport writeMap(const Image& image, const MapInfo& info, const std::filesystem::path& path,
                        CubeLayout layout = CubeLayout::Cross, const WriteOptions& options = {});

/// Writes a whole mip chain (`levels`: level k of resolution max(1, N >> k), as environmentMipChain
/// or bakeMipChain make them) into one file at `path`, or, with CubeLayout::Faces, into six such
/// files, one per face. `info` describes level 0 and is stored with "mip_levels": the number of map
/// levels, and `levelValues` (if given, one JSON object per level) as "level_values".
///   - .exr: a tiled, MIP-mapped OpenEXR (writeTiledMipChain). OpenEXR halves each level, rounding
///     down, to 1 x 1, so below a map's last level (a cube cross of 1-texel faces, 4 x 3; a
///     paraboloid or lat-long map of 1 row, 2 x 1) it has one or two more levels.
///   - .ktx2, .ktx, .dds: a texture (writeTexture, options.texelFormat): a cube becomes a cube
///     texture whose level k holds the six faces of map level k, so its levels end with the map's;
///     a 2:1 map (paraboloid, lat-long) gets one more level, 1 x 1, so engines see a complete chain.
/// Each level beyond the map's holds, in every texel, the solid-angle-weighted mean of the map's
/// last level (mipTexelWeight). Needs a power-of-two resolution N and one of these extensions
/// (containerProblem): else Error(InvalidArgument).
MapWriteReport writeTiledMap(const std::vector<Image>& levels, const MapInfo& info, const std::filesystem::path& path,
                             CubeLayout layout = CubeLayout::Cross, const WriteOptions& options = {},
                             const std::vector<nlohmann::json>& levelValues = {});

/// The six face file names of a cube written with CubeLayout::Faces, in OpenGL face order.
std::vector<std::filesystem::path> cubeFacePaths(const std::filesystem::path& path);

/// The files writeMap writes or replaces for `path`, for a FilePlan: the file (or, for a cube with
/// CubeLayout::Faces, its six faces) and the metadata sidecar FILE.json beside each, which
/// writeImage writes or removes. Each carries `role`.
std::vector<FilePlan::Entry> mapOutputFiles(const std::filesystem::path& path, const std::string& role,
                                            bool cube = false, CubeLayout layout = CubeLayout::Cross);

/// STEM_mipK.EXT beside `path` (level 0 is `path` itself): where a map's mip level k >= 1 is written
/// when its levels are separate files (MipLayout::Files).
std::filesystem::path mipLevelPath(const std::filesystem::path& path, int level);

}  // namespace brdfbake
