#include <brdfbake/core/files.hpp>
#include <brdfbake/bake/cube_map.hpp>
#include <brdfbake/bake/map_file.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {
void checkSize(const Image& image, const Parameterization& map, const std::string& label) {
  if (image.width() != map.width() || image.height() != map.height()) {
    throw Error(Error::Kind::InvalidInput,
                label + ": image is " + std::to_string(image.width()) + " x " + std::to_string(image.height()) +
                    " but a " + std::string(toString(map.kind())) + " map of resolution " +
                    std::to_string(map.resolution()) + " is " + std::to_string(map.width()) + " x " +
                    std::to_string(map.height()));
  }
}
}  // namespace

bool hasMapMetadata(const Image& image) {
  return !image.metadata.empty() && image.metadata.contains("parameterization");
}

MapFile mapFromImage(Image image, const std::string& label) {
  if (!hasMapMetadata(image)) {
    throw Error(Error::Kind::InvalidInput,
                label + ": not a brdfbake map (no brdfbake metadata); for a plain environment image, say "
                        "which parameterization it uses");
  }
  MapFile file;
  file.image = std::move(image);
  try {
    file.info = MapInfo::fromJson(file.image.metadata);
  } catch (const Error& e) {
    throw Error(e.kind(), label + ": " + e.what());
  }
  file.parameterization = makeParameterization(file.info.parameterization, file.info.resolution);
  checkSize(file.image, *file.parameterization, label);
  requireFinite(file.image, label);
  return file;
}

MapFile readMap(const fs::path& path) { return mapFromImage(readImage(path), path.string()); }

MapFile adoptImage(Image image, ParameterizationKind kind, const std::string& label) {
  int resolution = 0;
  switch (kind) {
    case ParameterizationKind::Sphere: resolution = image.width(); break;
    case ParameterizationKind::Paraboloid:
    case ParameterizationKind::LatLong: resolution = image.height(); break;
    case ParameterizationKind::Cube: resolution = image.width() / 4; break;
  }
  if (resolution < 1) throw Error(Error::Kind::InvalidInput, label + ": image too small for a " + std::string(toString(kind)) + " map");
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

std::vector<FilePlan::Entry> mapOutputFiles(const fs::path& path, const std::string& role, bool cube, CubeLayout layout) {
  std::vector<FilePlan::Entry> out;
  for (const auto& file : cube && layout == CubeLayout::Faces ? cubeFacePaths(path) : std::vector{path}) {
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
      if (sameFile(input, facePath)) throw Error(Error::Kind::InvalidArgument, facePath.string() + ": output would overwrite an input");
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
