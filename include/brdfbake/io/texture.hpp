#pragma once
/// @file
/// Textures as engines load them: levels x faces of float RGBA images in one file, KTX2 (Khronos
/// KTX 2.0), KTX1 (KTX 1.1, for OpenGL engines) or DDS with the DX10 header (docs/containers.md).
///
/// Conventions (docs/conventions.md, "Texture containers"): a cube texture has 6 faces in the
/// order +X, -X, +Y, -Y, +Z, -Z, each exactly the face of brdfbake's cube cross (row 0, the top
/// row, first in the file), which is what Vulkan, OpenGL and Direct3D sample: a lookup at a
/// map-frame direction d is `texture(samplerCube, d)`. Every image is stored with row 0 first and
/// KTXorientation "rd". Level k is max(1, W >> k) x max(1, H >> k).
///
/// Metadata: KTX2 and KTX1 hold brdfbake's metadata JSON in the key/value entry
/// "brdfbake.metadata" (with "KTXwriter" and "KTXorientation"); DDS holds none, so writeTexture
/// puts it in the sidecar PATH.json, as writeImage does for formats that drop it. Per-level values
/// (the roughness of each level of a GGX chain) go in the metadata's "level_values" array
/// (levelValues, map_file.hpp).

#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// The containers. Chosen by extension: .ktx2, .ktx, .dds.
enum class TextureContainer { Ktx2, Ktx1, Dds };

/// "KTX2", "KTX1", "DDS".
std::string_view toString(TextureContainer container);
/// The container for a path's extension (case-insensitive), or nullopt for any other extension.
std::optional<TextureContainer> textureContainerFor(const std::filesystem::path& path);
/// The container a file's first bytes identify (KTX2 and KTX1 identifiers, "DDS "), or nullopt.
std::optional<TextureContainer> textureContainerOf(std::string_view firstBytes);
/// Why `container` cannot store `format` ("" if it can): DDS has no 3-channel half format.
std::string texelFormatProblem(TextureContainer container, TexelFormat format);

/// The key of brdfbake's metadata in KTX key/value data.
inline constexpr const char* kMetadataKey = "brdfbake.metadata";

/// A texture: `levels[k][f]` is face f of level k (1 face, or 6 for a cube in the order above),
/// level 0 the largest.
struct Texture {
  std::vector<std::vector<Image>> levels;
  /// brdfbake's metadata (a JSON object; may be empty).
  nlohmann::json metadata = nlohmann::json::object();

  int levelCount() const { return static_cast<int>(levels.size()); }
  int faceCount() const { return levels.empty() ? 0 : static_cast<int>(levels[0].size()); }
  bool isCube() const { return faceCount() == 6; }
  int width() const { return levels.empty() || levels[0].empty() ? 0 : levels[0][0].width(); }
  int height() const { return levels.empty() || levels[0].empty() ? 0 : levels[0][0].height(); }
  /// Throws Error(InvalidArgument) "<label>: ..." unless there is at least one level, every level has
  /// 1 or 6 faces (the same count), cube faces are square, level k is max(1, W >> k) x
  /// max(1, H >> k), there are at most floor(log2(max(W, H))) + 1 levels, the size is at most
  /// kMaxTextureSize, and every value is finite.
  void validate(const std::string& label) const;
};

/// The largest width or height brdfbake writes or reads (65536 texels, beyond every GPU's limit).
inline constexpr int kMaxTextureSize = 65536;

/// The file's bytes and what encoding changed (encodingNotes).
struct EncodedTexture {
  std::string bytes;
  std::vector<std::string> notes;
};

/// Encodes a texture (validate()d first; Error(InvalidArgument) names `label`) as a whole file.
/// KTX2: levels smallest first, each aligned to lcm(texel size, 4), no supercompression, the Basic
/// Data Format Descriptor of `format`, key/value data sorted by key. KTX1: level 0 first, rows
/// padded to 4 bytes. DDS: the DX10 header, faces outer and levels inner. Throws
/// Error(InvalidArgument) if the container cannot hold `format` (texelFormatProblem).
EncodedTexture encodeTexture(const Texture& texture, TextureContainer container, TexelFormat format,
                             const std::string& label = "texture");

/// What a container file says about itself, read and checked without decoding texels.
struct TextureHeader {
  TextureContainer container = TextureContainer::Ktx2;
  TexelFormat format = TexelFormat::Rgba16Float;
  int width = 0, height = 0, faces = 0, levels = 0;
  /// brdfbake's metadata from the key/value data (empty object if absent, and always for DDS).
  nlohmann::json metadata = nlohmann::json::object();
  /// Key/value entries whose values are text, in file order (KTX2, KTX1), e.g. {"KTXwriter", "brdfbake 0.9.0"}.
  std::vector<std::pair<std::string, std::string>> keyValues;
};

/// Parses and checks a whole container file held in `bytes`; `label` (the file) starts every
/// message. Refused with Error(InvalidInput): a wrong identifier; a file shorter than its header
/// or sections; level offsets or lengths beyond the file or not matching the size and format;
/// sizes of 0 or above kMaxTextureSize; more levels than the size allows; array, 3-D and
/// supercompressed textures; formats other than those of TexelFormat; incomplete cube maps;
/// malformed key/value data or metadata JSON. Nothing is allocated beyond what the file holds.
TextureHeader readTextureHeader(std::string_view bytes, const std::string& label);

/// readTextureHeader, then decodes level `level` only (all levels if nullopt); the texture's
/// `levels` then has one entry (or all). Refuses non-finite texels (Error(InvalidInput) naming
/// level, face and texel) and decodes within the memory budget (Error(Resource)).
Texture decodeTexture(std::string_view bytes, const std::string& label, std::optional<int> level = std::nullopt);

/// Writes a texture atomically (AtomicOutput) in the container of the path's extension, with
/// `options.texelFormat` (Rgba16Float if unset). DDS: the metadata goes to the sidecar PATH.json
/// (metadataSidecarPath); KTX: a stale sidecar is removed. Throws Error(InvalidArgument) if `path`
/// is one of `options.inputs`, has another extension, or the texture is invalid; Error(Io) on failure.
WriteReport writeTexture(const Texture& texture, const std::filesystem::path& path, const WriteOptions& options = {});

/// Reads a container file (whole, within the memory budget), level `level` only or all levels,
/// with its metadata (from the sidecar PATH.json when the file holds none). Throws Error(Io) if
/// the file is missing, Error(InvalidInput) naming the file for anything readTextureHeader or
/// decodeTexture refuses, and if `level` is beyond the file's levels.
Texture readTexture(const std::filesystem::path& path, std::optional<int> level = std::nullopt);
/// The header only (readTextureHeader on the file), metadata from the sidecar as readTexture.
TextureHeader readTextureHeaderOf(const std::filesystem::path& path);

/// True if `image` is a cube map cross as writeMap writes it (metadata "parameterization" "cube",
/// 4N x 3N for its "resolution" N, not one of six face files): the image writeImage turns into a
/// cube texture.
bool isCubeCross(const Image& image);
/// The six faces of a cube cross (CubeMap regions), in texture order.
std::vector<Image> cubeFacesOfCross(const Image& cross);
/// The cross of six N x N faces: unused cells 0 with alpha 0.
Image crossOfCubeFaces(const std::vector<Image>& faces);

}  // namespace brdfbake
