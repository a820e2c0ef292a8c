#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <algorithm>
#include <functional>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {
void checkSize(const Image& image, const Parameterization& map, const std::string& label) {
  if (image.width() != map.width() || image.height() != map.height()) {
    throw Error(Error::Kind::InvalidInput, printable(label) + ": image is " + std::to_string(image.width()) + " x " +
                                               std::to_string(image.height()) + " but a " +
                                               std::string(toString(map.kind())) + " map of resolution " +
                                               std::to_string(map.resolution()) + " is " + std::to_string(map.width()) +
                                               " x " + std::to_string(map.height()));
  }
}
}  // namespace

bool hasMapMetadata(const Image& image) {
  return !image.metadata.empty() && image.metadata.contains("parameterization");
}

MapFile mapFromImage(Image image, const std::string& label) {
  if (!hasMapMetadata(image)) {
    throw Error(Error::Kind::InvalidInput,
                printable(label) +
                    ": not a brdfbake map (no brdfbake metadata); for a plain environment image, say "
                    "which parameterization it uses");
  }
  MapFile file;
  file.image = std::move(image);
  try {
    file.info = MapInfo::fromJson(file.image.metadata);
  } catch (const Error& e) {
    throw Error(e.kind(), printable(label) + ": " + e.what());
  }
  file.parameterization = makeParameterization(file.info.parameterization, file.info.resolution);
  checkSize(file.image, *file.parameterization, label);
  requireFinite(file.image, label);
  return file;
}

std::vector<fs::path> cubeFaceSet(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    const auto faces = cubeFacePaths(path);
    for (const auto& face : faces) {
      if (!fs::exists(face, ec)) return {};
    }
    return faces;
  }
  // A face file: STEM_posx.EXT and so on; its metadata says so.
  const std::string stem = path.stem().string();
  if (stem.size() < 5) return {};
  const std::string suffix = stem.substr(stem.size() - 5);
  const auto faces = cubeFacePaths(path.parent_path() / (stem.substr(0, stem.size() - 5) + path.extension().string()));
  bool isFace = false;
  for (const auto& face : faces) isFace = isFace || face.filename() == path.filename();
  if (!isFace) return {};
  const Image image = readImage(path);
  if (metadataValue(image.metadata, "layout", std::string()) != "faces") return {};
  return faces;
}

Image assembleCubeCross(const std::vector<fs::path>& faces, int mipLevel) {
  require(faces.size() == 6, "assembleCubeCross: a cube has six faces");
  std::vector<Image> images;
  for (const auto& face : faces) images.push_back(readImage(face, mipLevel));
  const int n = images[0].width();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (images[f].width() != n || images[f].height() != n) {
      throw Error(Error::Kind::InvalidInput,
                  faces[f].string() + ": cube face is " + std::to_string(images[f].width()) + " x " +
                      std::to_string(images[f].height()) + " but " + faces[0].string() + " is " + std::to_string(n) +
                      " x " + std::to_string(images[0].height()) + "; the six faces must be square and equal");
    }
  }
  const CubeMap cube(n);
  Image cross(4 * n, 3 * n, Rgba(0, 0, 0, 0));
  for (int f = 0; f < 6; ++f) {
    const TexelRect rect = cube.region(f);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) cross.set(rect.x0 + x, rect.y0 + y, images[static_cast<std::size_t>(f)].at(x, y));
  }
  cross.metadata = images[0].metadata;
  if (cross.metadata.is_object()) {
    cross.metadata.erase("layout");
    cross.metadata.erase("face");
  }
  return cross;
}

namespace {
// Level `level` of a MIP-mapped map file: its metadata describes level 0.
Image readTiledLevel(const fs::path& path, int level, const std::function<Image(int)>& read) {
  Image image = read(level);
  if (!hasMapMetadata(image)) return image;
  const int resolution = metadataValue(image.metadata, "resolution", 0);
  if (resolution < 1) return image;  // no valid resolution: mapFromImage refuses it, naming the file
  if ((resolution >> level) < 1) {
    throw Error(Error::Kind::InvalidInput,
                path.string() + ": MIP level " + std::to_string(level) + " lies below the map's " +
                    "1-texel level (OpenEXR's last levels hold only the map's mean); the map has " +
                    std::to_string(mipLevelCount(resolution)) + " levels");
  }
  image.metadata["resolution"] = resolution >> level;
  image.metadata["mip_level"] = level;
  return image;
}
}  // namespace

MapFile readMap(const fs::path& path, int mipLevel) {
  require(mipLevel >= 0, "MIP level must be >= 0");
  const auto faces = cubeFaceSet(path);
  if (!faces.empty()) {
    const std::string label = faces[0].string() + " (one of six cube faces)";
    if (mipLevel > 0 && imageMipLevelCount(faces[0]) == 1) {
      const fs::path stem =
          faces[0].parent_path() /
          (faces[0].stem().string().substr(0, faces[0].stem().string().size() - 5) + faces[0].extension().string());
      return mapFromImage(assembleCubeCross(cubeFacePaths(mipLevelPath(stem, mipLevel))), label);
    }
    return mapFromImage(readTiledLevel(faces[0], mipLevel, [&](int level) { return assembleCubeCross(faces, level); }),
                        label);
  }
  if (mipLevel > 0 && imageMipLevelCount(path) == 1) {
    const fs::path level = mipLevelPath(path, mipLevel);
    std::error_code ec;
    if (!fs::exists(level, ec)) {
      throw Error(Error::Kind::Io, path.string() + ": not MIP-mapped, and there is no level file " + level.string());
    }
    return readMap(level);
  }
  return mapFromImage(readTiledLevel(path, mipLevel, [&](int level) { return readImage(path, level); }), path.string());
}

std::string containerProblem(const fs::path& path, const OutputShape& shape) {
  ImageFormat format = ImageFormat::OpenExr;
  try {
    format = imageFormatFor(path);
  } catch (const Error& e) {
    return e.what();
  }
  const bool texture = isTextureContainer(format);
  if (shape.texelFormat) {
    const std::string name(toString(*shape.texelFormat));
    if (!texture) return path.string() + ": a texel format (" + name + ") applies to .ktx2, .ktx and .dds outputs only";
    if (const std::string problem = texelFormatProblem(*textureContainerFor(path), *shape.texelFormat);
        !problem.empty()) {
      return path.string() + ": " + problem;
    }
  }
  const int n = shape.resolution;
  if (shape.wholeChain) {
    if (format != ImageFormat::OpenExr && !texture) {
      return path.string() +
             ": a whole mip chain in one file needs .exr (a tiled MIP-mapped OpenEXR), .ktx2, .ktx or .dds; this "
             "format holds one image (write the levels as files instead)";
    }
    if (n < 1 || (n & (n - 1)) != 0) {
      return path.string() + ": a whole mip chain in one " + (texture ? "texture" : "tiled MIP-mapped OpenEXR") +
             " needs a power-of-two resolution (each map level must halve exactly, as the file's levels do), got " +
             std::to_string(n);
    }
  }
  if (texture && shape.parameterization && n > 0) {
    const bool cubeTexture = *shape.parameterization == ParameterizationKind::Cube;
    const auto map = makeParameterization(*shape.parameterization, n);
    const long long width = cubeTexture ? n : map->width(), height = cubeTexture ? n : map->height();
    if (width > kMaxTextureSize || height > kMaxTextureSize) {
      return path.string() + ": a " + std::to_string(width) + " x " + std::to_string(height) +
             " texture is larger than brdfbake's texture limit of " + std::to_string(kMaxTextureSize) + " texels";
    }
  }
  return {};
}

std::string tiledMipProblem(const fs::path& path, int resolution) {
  OutputShape shape;
  shape.resolution = resolution;
  shape.wholeChain = true;
  return containerProblem(path, shape);
}

nlohmann::json levelValues(const nlohmann::json& metadata, int level) {
  if (!metadata.is_object() || level < 0) return nlohmann::json::object();
  const auto values = metadata.find("level_values");
  if (values == metadata.end() || !values->is_array() || static_cast<std::size_t>(level) >= values->size()) {
    return nlohmann::json::object();
  }
  const nlohmann::json& value = (*values)[static_cast<std::size_t>(level)];
  return value.is_object() ? value : nlohmann::json::object();
}

namespace {
// The map's levels, then (down to the size the file's format ends at) levels holding the
// solid-angle-weighted mean of the map's last level in every texel.
std::vector<Image> completedChain(const std::vector<Image>& levels, const MapInfo& info) {
  std::vector<Image> chain = levels;
  const auto last = makeParameterization(info.parameterization, std::max(1, info.resolution >> (levels.size() - 1)));
  Rgba sum = Rgba::Zero();
  double weight = 0.0;
  for (int y = 0; y < last->height(); ++y)
    for (int x = 0; x < last->width(); ++x) {
      const double w = mipTexelWeight(*last, x, y);
      sum += w * chain.back().at(x, y);
      weight += w;
    }
  const Rgba mean = weight > 0.0 ? Rgba(sum / weight) : Rgba::Zero();
  while (chain.back().width() > 1 || chain.back().height() > 1) {
    chain.emplace_back(std::max(1, chain.back().width() / 2), std::max(1, chain.back().height() / 2), mean);
  }
  return chain;
}

// One file holding `chain` (1 face) or `faces` (6 faces per level), in the path's format.
void writeChainFile(const std::vector<std::vector<Image>>& levels, const nlohmann::json& metadata, const fs::path& path,
                    const std::string& wrap, const WriteOptions& options, MapWriteReport& report) {
  WriteReport written;
  if (isTextureContainer(imageFormatFor(path))) {
    Texture texture;
    texture.levels = levels;
    texture.metadata = metadata;
    written = writeTexture(texture, path, options);
  } else {
    std::vector<Image> chain;
    for (const auto& level : levels) chain.push_back(level[0]);
    written = writeTiledMipChain(chain, metadata, path, wrap, options);
  }
  report.files.push_back(path);
  for (const std::string& note : written.notes)
    if (std::find(report.notes.begin(), report.notes.end(), note) == report.notes.end()) report.notes.push_back(note);
}
}  // namespace

MapWriteReport writeTiledMap(const std::vector<Image>& levels, const MapInfo& info, const fs::path& path,
                             CubeLayout layout, const WriteOptions& options,
                             const std::vector<nlohmann::json>& levelValues) {
  require(!levels.empty(), "writeTiledMap: no levels");
  const int n = info.resolution;
  OutputShape shape;
  shape.parameterization = info.parameterization;
  shape.resolution = n;
  shape.wholeChain = true;
  shape.cubeLayout = layout;
  shape.texelFormat = options.texelFormat;
  if (const std::string problem = containerProblem(path, shape); !problem.empty())
    throw Error(Error::Kind::InvalidArgument, problem);
  if (static_cast<int>(levels.size()) != mipLevelCount(n)) {
    throw Error(Error::Kind::InvalidArgument, "writeTiledMap: a map of resolution " + std::to_string(n) + " has " +
                                                  std::to_string(mipLevelCount(n)) + " levels, got " +
                                                  std::to_string(levels.size()));
  }
  require(levelValues.empty() || levelValues.size() == levels.size(),
          "writeTiledMap: level values need one object per level");
  nlohmann::json metadata = info.toJson();
  metadata["mip_levels"] = static_cast<int>(levels.size());
  if (!levelValues.empty()) metadata["level_values"] = levelValues;
  const std::string wrap = info.parameterization == ParameterizationKind::LatLong ? "periodic,clamp" : "clamp,clamp";
  const bool texture = isTextureContainer(imageFormatFor(path));
  MapWriteReport report;
  if (info.parameterization == ParameterizationKind::Cube) {
    // Each face halves to 1 x 1 exactly with the map: no extra levels.
    std::vector<std::vector<std::vector<Image>>> faces(6);  // [face][level][0]
    std::vector<std::vector<Image>> cube;                   // [level][face]
    for (const Image& level : levels) {
      std::vector<Image> six = cubeFacesOfCross(level);
      for (int f = 0; f < 6; ++f) faces[static_cast<std::size_t>(f)].push_back({six[static_cast<std::size_t>(f)]});
      cube.push_back(std::move(six));
    }
    if (layout == CubeLayout::Faces) {
      const auto paths = cubeFacePaths(path);
      for (int f = 0; f < 6; ++f) {
        nlohmann::json faceMetadata = metadata;
        faceMetadata["layout"] = "faces";
        faceMetadata["face"] = std::string(CubeMap::faceName(static_cast<CubeMap::Face>(f)));
        writeChainFile(faces[static_cast<std::size_t>(f)], faceMetadata, paths[static_cast<std::size_t>(f)], wrap,
                       options, report);
      }
      return report;
    }
    if (texture) {
      writeChainFile(cube, metadata, path, wrap, options, report);
      return report;
    }
  }
  const std::vector<Image> chain = completedChain(levels, info);
  std::vector<std::vector<Image>> oneFace;
  for (const Image& level : chain) oneFace.push_back({level});
  writeChainFile(oneFace, metadata, path, wrap, options, report);
  if (chain.size() > levels.size()) {
    report.notes.push_back(path.filename().string() + ": " + std::to_string(levels.size()) + " map levels in one " +
                           (texture ? "texture" : "tiled MIP-mapped OpenEXR") + "; its " +
                           std::to_string(chain.size() - levels.size()) + " further level(s) hold the map's mean");
  }
  return report;
}

MapFile adoptImage(Image image, ParameterizationKind kind, const std::string& label) {
  int resolution = 0;
  switch (kind) {
    case ParameterizationKind::Sphere:
      resolution = image.width();
      break;
    case ParameterizationKind::Paraboloid:
    case ParameterizationKind::LatLong:
      resolution = image.height();
      break;
    case ParameterizationKind::Cube:
      resolution = image.width() / 4;
      break;
  }
  if (resolution < 1)
    throw Error(Error::Kind::InvalidInput,
                printable(label) + ": image too small for a " + std::string(toString(kind)) + " map");
  MapFile file;
  file.parameterization = makeParameterization(kind, resolution);
  checkSize(image, *file.parameterization, label);
  requireFinite(image, label);
  file.info.parameterization = kind;
  file.info.resolution = resolution;
  file.info.conventionVersion = kConventionVersion;
  file.image = std::move(image);
  return file;
}

std::vector<FilePlan::Entry> mapOutputFiles(const fs::path& path, const std::string& role, bool cube,
                                            CubeLayout layout) {
  std::vector<FilePlan::Entry> out;
  for (const auto& file : cube&& layout == CubeLayout::Faces ? cubeFacePaths(path) : std::vector{path}) {
    out.push_back({file, role});
    out.push_back({metadataSidecarPath(file), role + " (metadata sidecar)"});
  }
  return out;
}

std::vector<fs::path> cubeFacePaths(const fs::path& path) {
  static const char* suffixes[6] = {"_posx", "_negx", "_posy", "_negy", "_posz", "_negz"};
  std::vector<fs::path> paths;
  for (const char* suffix : suffixes) {
    paths.push_back(siblingWithSuffix(path, suffix));
  }
  return paths;
}

MapWriteReport writeMap(const Image& image, const MapInfo& info, const fs::path& path, CubeLayout layout,
                        const WriteOptions& options) {
  MapWriteReport report;
  auto note = [&](const WriteReport& r) { report.notes.insert(report.notes.end(), r.notes.begin(), r.notes.end()); };
  if (info.parameterization != ParameterizationKind::Cube || layout == CubeLayout::Cross) {
    Image out = image;
    out.metadata = info.toJson();
    note(writeImage(out, path, options));
    report.files.push_back(path);
    return report;
  }
  const int n = info.resolution;
  const CubeMap cube(n);
  const auto paths = cubeFacePaths(path);
  for (const auto& facePath : paths) {
    for (const auto& input : options.inputs) {
      if (sameFile(input, facePath))
        throw Error(Error::Kind::InvalidArgument, facePath.string() + ": output would overwrite an input");
    }
  }
  for (int f = 0; f < 6; ++f) {
    const TexelRect rect = cube.region(f);
    Image face(n, n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) face.set(x, y, image.at(rect.x0 + x, rect.y0 + y));
    face.metadata = info.toJson();
    face.metadata["layout"] = "faces";
    face.metadata["face"] = std::string(CubeMap::faceName(static_cast<CubeMap::Face>(f)));
    note(writeImage(face, paths[f], options));
    report.files.push_back(paths[f]);
  }
  return report;
}

std::filesystem::path mipLevelPath(const std::filesystem::path& path, int level) {
  if (level == 0) return path;
  return siblingWithSuffix(path, "_mip" + std::to_string(level));
}

}  // namespace brdfbake
