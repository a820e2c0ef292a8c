#pragma once
/// @file
/// Maps on disk: an image plus the MapInfo that says how to read it.

#include <brdfbake/core/files.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/image_io.hpp>

#include <filesystem>
#include <memory>

namespace brdfbake {

/// How a cube map is written: one 4N x 3N horizontal cross, or six N x N files
/// STEM_posx.EXT, STEM_negx.EXT, STEM_posy.EXT, STEM_negy.EXT, STEM_posz.EXT, STEM_negz.EXT.
enum class CubeLayout { Cross, Faces };

/// How a mip chain is written: each level a map of its own (level k >= 1 at STEM_mipK.EXT,
/// mipLevelPath), or the whole chain in one tiled, MIP-mapped OpenEXR (writeTiledMap), as
/// OpenImageIO's make_texture / maketx write textures.
enum class MipLayout { Files, Tiled };

/// Why a chain of a map of `resolution` cannot be written tiled at `path` ("" if it can): the
/// path must be .exr and the resolution a power of two. For checks before any work.
std::string tiledMipProblem(const std::filesystem::path& path, int resolution);

/// A map read back from disk.
struct MapFile {
  Image image;
  MapInfo info;
  std::unique_ptr<Parameterization> parameterization;
};

/// Reads a map written by writeMap or writeTiledMap: one file, or a cube's six faces
/// (CubeLayout::Faces), named by STEM.EXT (which then need not exist) or by any one face file.
/// `mipLevel` > 0 reads that level of the chain: from the file itself if it is MIP-mapped
/// (writeTiledMap), else from STEM_mipK.EXT (mipLevelPath). Throws Error(InvalidInput) if the
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
/// files written and the notes of writeImage.
struct MapWriteReport {
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;
};
MapWriteReport writeMap(const Image& image, const MapInfo& info, const std::filesystem::path& path,
                        CubeLayout layout = CubeLayout::Cross, const WriteOptions& options = {});

/// Writes a whole mip chain (`levels`: level k of resolution max(1, N >> k), as environmentMipChain
/// or bakeMipChain make them) into one tiled, MIP-mapped OpenEXR at `path` (writeTiledMipChain),
/// or, with CubeLayout::Faces, into six such files, one per face. `info` describes level 0 and is
/// stored with "mip_levels": the number of map levels. OpenEXR halves each level, rounding down,
/// to 1 x 1, so below a map's last level (a cube cross of 1-texel faces, 4 x 3; a paraboloid or
/// lat-long map of 1 row, 2 x 1) it has one or two more levels: each holds, in every texel, the
/// solid-angle-weighted mean of the map's last level (mipTexelWeight). Needs a power-of-two
/// resolution N (so every level has OpenEXR's size) and a .exr path: else Error(InvalidArgument).
MapWriteReport writeTiledMap(const std::vector<Image>& levels, const MapInfo& info, const std::filesystem::path& path,
                             CubeLayout layout = CubeLayout::Cross, const WriteOptions& options = {});

/// The six face file names of a cube written with CubeLayout::Faces, in OpenGL face order.
std::vector<std::filesystem::path> cubeFacePaths(const std::filesystem::path& path);

/// The files writeMap writes or replaces for `path`, for a FilePlan: the file (or, for a cube with
/// CubeLayout::Faces, its six faces) and the metadata sidecar FILE.json beside each, which
/// writeImage writes or removes. Each carries `role`.
std::vector<FilePlan::Entry> mapOutputFiles(const std::filesystem::path& path, const std::string& role,
                                            bool cube = false, CubeLayout layout = CubeLayout::Cross);

}  // namespace brdfbake
