#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/maps/map_mips.hpp>

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
  if (image.metadata.value("layout", "") != "faces") return {};
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
  const int resolution = image.metadata.value("resolution", 0);
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

std::string tiledMipProblem(const fs::path& path, int resolution) {
  if (imageFormatFor(path) != ImageFormat::OpenExr) {
    return path.string() + ": a tiled MIP-mapped file must be OpenEXR (.exr)";
  }
  if (resolution < 1 || (resolution & (resolution - 1)) != 0) {
    return "a tiled MIP-mapped OpenEXR needs a power-of-two resolution (OpenEXR halves each level, rounding down), "
           "got " +
           std::to_string(resolution);
  }
  return {};
}

MapWriteReport writeTiledMap(const std::vector<Image>& levels, const MapInfo& info, const fs::path& path,
                             CubeLayout layout, const WriteOptions& options) {
  require(!levels.empty(), "writeTiledMap: no levels");
  const int n = info.resolution;
  if (const std::string problem = tiledMipProblem(path, n); !problem.empty())
    throw Error(Error::Kind::InvalidArgument, problem);
  if (static_cast<int>(levels.size()) != mipLevelCount(n)) {
    throw Error(Error::Kind::InvalidArgument, "writeTiledMap: a map of resolution " + std::to_string(n) + " has " +
                                                  std::to_string(mipLevelCount(n)) + " levels, got " +
                                                  std::to_string(levels.size()));
  }
  nlohmann::json metadata = info.toJson();
  metadata["mip_levels"] = static_cast<int>(levels.size());
  const std::string wrap = info.parameterization == ParameterizationKind::LatLong ? "periodic,clamp" : "clamp,clamp";
  MapWriteReport report;
  if (info.parameterization == ParameterizationKind::Cube && layout == CubeLayout::Faces) {
    // Each face halves to 1 x 1 exactly with the map: no extra levels.
    const auto paths = cubeFacePaths(path);
    for (int f = 0; f < 6; ++f) {
      std::vector<Image> faces;
      for (std::size_t k = 0; k < levels.size(); ++k) {
        const int m = std::max(1, n >> k);
        const TexelRect rect = CubeMap(m).region(f);
        Image face(m, m);
        for (int y = 0; y < m; ++y)
          for (int x = 0; x < m; ++x) face.set(x, y, levels[k].at(rect.x0 + x, rect.y0 + y));
        faces.push_back(std::move(face));
      }
      nlohmann::json faceMetadata = metadata;
      faceMetadata["layout"] = "faces";
      faceMetadata["face"] = std::string(CubeMap::faceName(static_cast<CubeMap::Face>(f)));
      writeTiledMipChain(faces, faceMetadata, paths[static_cast<std::size_t>(f)], wrap, options);
      report.files.push_back(paths[static_cast<std::size_t>(f)]);
    }
    return report;
  }
  // Below the map's last level: its solid-angle-weighted mean in every texel, down to 1 x 1.
  std::vector<Image> chain = levels;
  const auto last = makeParameterization(info.parameterization, std::max(1, n >> (levels.size() - 1)));
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
  writeTiledMipChain(chain, metadata, path, wrap, options);
  report.files.push_back(path);
  if (chain.size() > levels.size()) {
    report.notes.push_back(path.filename().string() + ": " + std::to_string(levels.size()) +
                           " map levels in one tiled MIP-mapped "
                           "OpenEXR; OpenEXR's " +
                           std::to_string(chain.size() - levels.size()) +
                           " further level(s) hold the "
                           "map's mean");
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

}  // namespace brdfbake
