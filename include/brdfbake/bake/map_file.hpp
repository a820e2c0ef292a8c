#pragma once
/// @file
/// Maps on disk: an image plus the MapInfo that says how to read it.

#include <brdfbake/bake/image.hpp>
#include <brdfbake/bake/image_io.hpp>
#include <brdfbake/core/files.hpp>

#include <filesystem>
#include <memory>

namespace brdfbake {

/// How a cube map is written: one 4N x 3N horizontal cross, or six N x N files
/// STEM_posx.EXT, STEM_negx.EXT, STEM_posy.EXT, STEM_negy.EXT, STEM_posz.EXT, STEM_negz.EXT.
enum class CubeLayout { Cross, Faces };

/// A map read back from disk.
struct MapFile {
  Image image;
  MapInfo info;
  std::unique_ptr<Parameterization> parameterization;
};

/// Reads a map written by writeMap (cross layout for cubes). Throws Error(InvalidInput) if the
/// file has no brdfbake metadata, its size does not match the metadata, or a texel is NaN or
/// infinite.
MapFile readMap(const std::filesystem::path& path);

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

/// The six face file names of a cube written with CubeLayout::Faces, in OpenGL face order.
std::vector<std::filesystem::path> cubeFacePaths(const std::filesystem::path& path);

/// The files writeMap writes or replaces for `path`, for a FilePlan: the file (or, for a cube with
/// CubeLayout::Faces, its six faces) and the metadata sidecar FILE.json beside each, which
/// writeImage writes or removes. Each carries `role`.
std::vector<FilePlan::Entry> mapOutputFiles(const std::filesystem::path& path, const std::string& role,
                                            bool cube = false, CubeLayout layout = CubeLayout::Cross);

}  // namespace brdfbake
