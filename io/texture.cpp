// Textures in KTX2, KTX1 and DDS files (texture.hpp): the container-neutral part.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_text.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "texture_codecs.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
using namespace texture_detail;

std::string_view toString(TextureContainer container) {
  switch (container) {
    case TextureContainer::Ktx2:
      return "KTX2";
    case TextureContainer::Ktx1:
      return "KTX1";
    case TextureContainer::Dds:
      return "DDS";
  }
  return "KTX2";
}

std::optional<TextureContainer> textureContainerFor(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ktx2") return TextureContainer::Ktx2;
  if (ext == ".ktx") return TextureContainer::Ktx1;
  if (ext == ".dds") return TextureContainer::Dds;
  return std::nullopt;
}

std::optional<TextureContainer> textureContainerOf(std::string_view first) {
  static const char kKtx2[] = "\xABKTX 20\xBB\r\n\x1A\n", kKtx1[] = "\xABKTX 11\xBB\r\n\x1A\n";
  if (first.size() >= 12 && std::memcmp(first.data(), kKtx2, 12) == 0) return TextureContainer::Ktx2;
  if (first.size() >= 12 && std::memcmp(first.data(), kKtx1, 12) == 0) return TextureContainer::Ktx1;
  if (first.size() >= 4 && std::memcmp(first.data(), "DDS ", 4) == 0) return TextureContainer::Dds;
  return std::nullopt;
}

std::string texelFormatProblem(TextureContainer container, TexelFormat format) {
  if (container == TextureContainer::Dds && format == TexelFormat::Rgb16Float) {
    return "DDS has no 3-channel half-float format (DXGI has no R16G16B16_FLOAT): use rgba16f or rgb32f";
  }
  return {};
}

void Texture::validate(const std::string& label) const {
  auto fail = [&](const std::string& message) { throw Error(Error::Kind::InvalidArgument, label + ": " + message); };
  if (levels.empty() || levels[0].empty()) fail("a texture needs at least one level with one face");
  const int faces = faceCount(), w = width(), h = height();
  if (faces != 1 && faces != 6) fail("a texture has 1 face or 6 (a cube), not " + std::to_string(faces));
  if (faces == 6 && w != h) fail("cube faces must be square, got " + std::to_string(w) + " x " + std::to_string(h));
  if (w > kMaxTextureSize || h > kMaxTextureSize) {
    fail("a " + std::to_string(w) + " x " + std::to_string(h) + " texture is larger than " +
         std::to_string(kMaxTextureSize) + " texels");
  }
  if (levelCount() > maxLevelCount(w, h)) {
    fail(std::to_string(levelCount()) + " levels, more than a " + std::to_string(w) + " x " + std::to_string(h) +
         " texture has (" + std::to_string(maxLevelCount(w, h)) + ")");
  }
  for (int k = 0; k < levelCount(); ++k) {
    const auto& level = levels[static_cast<std::size_t>(k)];
    if (static_cast<int>(level.size()) != faces) fail("level " + std::to_string(k) + " has another face count");
    const int lw = static_cast<int>(levelSize(w, k)), lh = static_cast<int>(levelSize(h, k));
    for (std::size_t f = 0; f < level.size(); ++f) {
      if (level[f].width() != lw || level[f].height() != lh) {
        fail("level " + std::to_string(k) + " face " + std::to_string(f) + " is " + std::to_string(level[f].width()) +
             " x " + std::to_string(level[f].height()) + ", expected " + std::to_string(lw) + " x " +
             std::to_string(lh) + " (max(1, size >> level))");
      }
      requireFinite(level[f], label + ": level " + std::to_string(k) + " face " + std::to_string(f));
    }
  }
}

EncodedTexture encodeTexture(const Texture& texture, TextureContainer container, TexelFormat format,
                             const std::string& label) {
  texture.validate(label);
  if (const std::string problem = texelFormatProblem(container, format); !problem.empty()) {
    throw Error(Error::Kind::InvalidArgument, label + ": " + problem);
  }
  EncodingTally tally;
  KeyValues keyValues{{"KTXwriter", std::string("brdfbake ") + BRDFBAKE_VERSION_STRING + '\0'}};
  keyValues.emplace_back("KTXorientation", std::string(container == TextureContainer::Ktx1 ? "S=r,T=d" : "rd") + '\0');
  if (!texture.metadata.empty()) keyValues.emplace_back(kMetadataKey, texture.metadata.dump() + '\0');
  EncodedTexture out;
  switch (container) {
    case TextureContainer::Ktx2:
      out.bytes = encodeKtx2(texture, format, keyValues, tally);
      break;
    case TextureContainer::Ktx1:
      out.bytes = encodeKtx1(texture, format, keyValues, tally);
      break;
    case TextureContainer::Dds:
      out.bytes = encodeDds(texture, format, tally);
      break;
  }
  out.notes = encodingNotes(tally, format);
  return out;
}

namespace {

ParsedTexture parse(std::string_view bytes, const std::string& label) {
  const auto container = textureContainerOf(bytes.substr(0, 12));
  if (!container) {
    throw Error(Error::Kind::InvalidInput, label + ": not a KTX2, KTX or DDS file (no identifier)");
  }
  switch (*container) {
    case TextureContainer::Ktx2:
      return parseKtx2(bytes, label);
    case TextureContainer::Ktx1:
      return parseKtx1(bytes, label);
    case TextureContainer::Dds:
      return parseDds(bytes, label);
  }
  return parseKtx2(bytes, label);
}

Image decodeImage(std::string_view bytes, const ImageSpan& span, int width, int height, TexelFormat format, bool rowsUp,
                  const std::string& label) {
  Image image(width, height);
  const std::uint64_t rowBytes = static_cast<std::uint64_t>(width) * bytesPerTexel(format);
  for (int y = 0; y < height; ++y) {
    const std::uint64_t offset = span.offset + span.rowPitch * static_cast<std::uint64_t>(y);
    require(offset + rowBytes <= bytes.size(), label + ": row beyond the file");  // parsers checked it
    const int row = rowsUp ? height - 1 - y : y;
    decodeTexels(reinterpret_cast<const unsigned char*>(bytes.data() + offset), static_cast<std::size_t>(width), format,
                 image.data() + image.index(0, row));
  }
  try {
    requireFinite(image, label);
  } catch (const Error& e) {
    throw Error(Error::Kind::InvalidInput, e.what());
  }
  return image;
}

}  // namespace

TextureHeader readTextureHeader(std::string_view bytes, const std::string& label) { return parse(bytes, label).header; }

Texture decodeTexture(std::string_view bytes, const std::string& label, std::optional<int> level) {
  const ParsedTexture parsed = parse(bytes, label);
  const TextureHeader& h = parsed.header;
  if (level && (*level < 0 || *level >= h.levels)) {
    throw Error(Error::Kind::InvalidInput, label + ": has " + std::to_string(h.levels) + " MIP level" +
                                               (h.levels == 1 ? "" : "s") + ", no level " + std::to_string(*level));
  }
  const int first = level.value_or(0), last = level ? *level : h.levels - 1;
  // Decoded floats: at most 4 floats per texel for every texel the file holds.
  double texels = 0.0;
  for (int k = first; k <= last; ++k)
    texels += double(levelSize(h.width, k)) * double(levelSize(h.height, k)) * h.faces;
  requireWithinMemoryBudget(texels * 4 * sizeof(float), label + ": decoding " + std::to_string(texels) + " texels");
  Texture texture;
  texture.metadata = h.metadata;
  for (int k = first; k <= last; ++k) {
    const int w = static_cast<int>(levelSize(h.width, k)), ht = static_cast<int>(levelSize(h.height, k));
    texture.levels.emplace_back();
    for (int f = 0; f < h.faces; ++f) {
      const std::string where =
          label + ": level " + std::to_string(k) +
          (h.faces == 6 ? " face " + std::string(CubeMap::faceName(static_cast<CubeMap::Face>(f))) : std::string());
      texture.levels.back().push_back(
          decodeImage(bytes, parsed.images[static_cast<std::size_t>(k)][static_cast<std::size_t>(f)], w, ht, h.format,
                      parsed.rowsUp, where));
    }
  }
  return texture;
}

WriteReport writeTexture(const Texture& texture, const fs::path& path, const WriteOptions& options) {
  for (const auto& input : options.inputs) {
    if (sameFile(input, path)) {
      throw Error(Error::Kind::InvalidArgument,
                  path.string() + ": output would overwrite an input; choose another output path");
    }
  }
  const auto container = textureContainerFor(path);
  if (!container) {
    throw Error(Error::Kind::InvalidArgument, path.string() + ": a texture is written as .ktx2, .ktx or .dds");
  }
  const TexelFormat format = options.texelFormat.value_or(TexelFormat::Rgba16Float);
  EncodedTexture encoded = encodeTexture(texture, *container, format, path.string());
  WriteReport report;
  report.notes = std::move(encoded.notes);
  AtomicOutput output(path);
  output.open();
  output.write(encoded.bytes);  // a full disk: "<path>: write failed: No space left on device (disk full)"
  const fs::path sidecar = metadataSidecarPath(path);
  if (*container == TextureContainer::Dds && !texture.metadata.empty()) {
    writeFileAtomically(sidecar, texture.metadata.dump(2) + "\n");
    report.sidecar = true;
    report.notes.push_back("DDS holds no metadata: written to " + sidecar.string());
  } else {
    std::error_code ec;
    fs::remove(sidecar, ec);  // a stale sidecar from an earlier write would contradict the file
  }
  output.commit();
  return report;
}

namespace {
std::string readWhole(const fs::path& path) {
  const std::uintmax_t size = requireInputFile(path, "texture");
  requireWithinMemoryBudget(static_cast<double>(size), path.string() + ": reading the file");
  return readTextFile(path, "texture", std::max<std::uintmax_t>(size, 1));
}

void metadataFromSidecar(nlohmann::json& metadata, const fs::path& path) {
  if (!metadata.empty()) return;
  if (nlohmann::json sidecar = readMetadataSidecar(path); !sidecar.is_null()) metadata = std::move(sidecar);
}
}  // namespace

Texture readTexture(const fs::path& path, std::optional<int> level) {
  const std::string bytes = readWhole(path);
  Texture texture = decodeTexture(bytes, path.string(), level);
  metadataFromSidecar(texture.metadata, path);
  return texture;
}

TextureHeader readTextureHeaderOf(const fs::path& path) {
  const std::string bytes = readWhole(path);
  TextureHeader header = readTextureHeader(bytes, path.string());
  metadataFromSidecar(header.metadata, path);
  return header;
}

bool isCubeCross(const Image& image) {
  const nlohmann::json& m = image.metadata;
  if (!m.is_object() || m.value("parameterization", nlohmann::json()) != "cube") return false;
  if (m.value("layout", nlohmann::json()) == "faces") return false;
  const auto resolution = m.find("resolution");
  if (resolution == m.end() || !resolution->is_number_integer()) return false;
  const long long n = resolution->get<long long>();
  return n >= 1 && image.width() == 4 * n && image.height() == 3 * n;
}

std::vector<Image> cubeFacesOfCross(const Image& cross) {
  const int n = cross.width() / 4;
  require(n >= 1 && cross.width() == 4 * n && cross.height() == 3 * n, "a cube cross is 4N x 3N");
  const CubeMap cube(n);
  std::vector<Image> faces;
  for (int f = 0; f < 6; ++f) {
    const TexelRect rect = cube.region(f);
    Image face(n, n);
    for (int y = 0; y < n; ++y)
      std::memcpy(face.data() + face.index(0, y), cross.data() + cross.index(rect.x0, rect.y0 + y),
                  sizeof(float) * 4 * static_cast<std::size_t>(n));
    faces.push_back(std::move(face));
  }
  return faces;
}

Image crossOfCubeFaces(const std::vector<Image>& faces) {
  require(faces.size() == 6, "a cube has six faces");
  const int n = faces[0].width();
  const CubeMap cube(n);
  Image cross(4 * n, 3 * n, Rgba(0, 0, 0, 0));
  for (int f = 0; f < 6; ++f) {
    const Image& face = faces[static_cast<std::size_t>(f)];
    require(face.width() == n && face.height() == n, "cube faces must be square and equal");
    const TexelRect rect = cube.region(f);
    for (int y = 0; y < n; ++y)
      std::memcpy(cross.data() + cross.index(rect.x0, rect.y0 + y), face.data() + face.index(0, y),
                  sizeof(float) * 4 * static_cast<std::size_t>(n));
  }
  return cross;
}

}  // namespace brdfbake
