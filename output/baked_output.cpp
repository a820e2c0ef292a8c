// Every output of bake and prefilter, opened for lookups as a renderer makes them (baked_output.hpp).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/json_text.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/output/baked_output.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

bool pathExists(const fs::path& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// A slice (or its six faces) of a stack exists at elevationSlicePath(path, 0).
bool isStack(const fs::path& path) {
  const fs::path first = elevationSlicePath(path, 0);
  return pathExists(first) || !cubeFaceSet(first).empty();
}

const nlohmann::json* elevationOf(const MapFile& map) {
  const auto& spec = map.info.spec;
  if (!spec.is_object() || !spec.contains("prefilter") || !spec["prefilter"].is_object()) return nullptr;
  const auto it = spec["prefilter"].find("elevation");
  return it != spec["prefilter"].end() && it->is_object() ? &*it : nullptr;
}

bool irradianceByNormal(const MapFile& map) {
  if (map.info.parameterization == ParameterizationKind::Sphere) return false;  // a sphere map holds E at r
  const auto& spec = map.info.spec;
  return spec.is_object() && spec.contains("prefilter") && spec["prefilter"].is_object() &&
         spec["prefilter"].value("lobe", "") == "irradiance";
}

// A prefiltered irradiance map (alone, or a Fresnel decomposition's): its "prefilter" object, else null.
const nlohmann::json* irradiancePrefilter(const MapFile& map) {
  const auto& spec = map.info.spec;
  if (!spec.is_object() || !spec.contains("prefilter") || !spec["prefilter"].is_object()) return nullptr;
  const nlohmann::json& p = spec["prefilter"];
  const bool fresnelIrradiance =
      p.contains("fresnel") && p["fresnel"].is_object() && p["fresnel"].value("role", "") == "irradiance";
  return p.value("lobe", "") == "irradiance" || fresnelIrradiance ? &p : nullptr;
}

// What lookups multiply a map's texels by so that irradiance comes out as E/pi: maps written before
// brdfbake stated the quantity ("irradiance_quantity" absent) hold E.
double irradianceScale(const MapFile& map) {
  const nlohmann::json* p = irradiancePrefilter(map);
  return p && !p->contains("irradiance_quantity") ? 1.0 / kPi : 1.0;
}

std::vector<Rgb> rowTexels(const Image& image) {
  std::vector<Rgb> texels;
  for (int x = 0; x < image.width(); ++x) texels.push_back(image.at(x, 0).head<3>());
  return texels;
}

void requireNoMipLevel(int mipLevel, const fs::path& path, const std::string& what) {
  if (mipLevel != 0) {
    throw Error(Error::Kind::InvalidArgument,
                path.string() + ": " + what + " has no mip levels (asked for level " + std::to_string(mipLevel) + ")");
  }
}

// A 1-D profile: N x 1 with "resolution" N.
void checkProfileImage(const Image& image, const fs::path& path) {
  const int resolution = metadataValue(image.metadata, "resolution", 0);
  if (image.height() != 1 || image.width() != resolution) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": a 1-D profile of resolution " +
                                               std::to_string(resolution) + " is " + std::to_string(resolution) +
                                               " x 1, but the image is " + std::to_string(image.width()) + " x " +
                                               std::to_string(image.height()));
  }
  requireFinite(image, path.string());
}

Vec3 axisOf(const nlohmann::json& metadata, const fs::path& path) {
  const auto axis = metadata.find("axis");
  if (axis == metadata.end() || !axis->is_array() || axis->size() != 3) {
    throw Error(Error::Kind::InvalidInput, path.string() + ": radial profile metadata has no valid 'axis' [x, y, z]");
  }
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!(*axis)[static_cast<std::size_t>(i)].is_number()) {
      throw Error(Error::Kind::InvalidInput, path.string() + ": radial profile 'axis' must hold three numbers");
    }
    v[i] = (*axis)[static_cast<std::size_t>(i)].get<double>();
  }
  const double scale = v.cwiseAbs().maxCoeff();
  if (!std::isfinite(scale) || scale == 0.0) {
    throw Error(Error::Kind::InvalidInput,
                path.string() + ": radial profile 'axis' must be a finite non-zero vector, got " + axis->dump());
  }
  return v / scale;
}

double checkedCosView(std::optional<double> cosView, OutputKind kind) {
  if (!cosView) {
    throw Error(Error::Kind::InvalidArgument,
                std::string("a ") + std::string(toString(kind)) +
                    " is looked up at n.v, the cosine between the normal and the view: give it");
  }
  if (!(*cosView >= 0.0 && *cosView <= 1.0)) {
    throw Error(Error::Kind::InvalidArgument, "n.v must be in [0, 1], got " + std::to_string(*cosView));
  }
  return *cosView;
}

// The slices of an elevation stack, slice 0 first, and the range of n.v they span: slice 0's
// spec.prefilter.elevation says how many slices there are; every slice must agree with it.
struct StackSlices {
  std::vector<MapFile> maps;
  double minCos = 1.0, maxCos = 1.0;
};

StackSlices readStackSlices(const fs::path& path, int mipLevel) {
  StackSlices stack;
  stack.maps.push_back(readMap(elevationSlicePath(path, 0), mipLevel));
  const nlohmann::json* elevation = elevationOf(stack.maps[0]);
  const std::string first = elevationSlicePath(path, 0).string();
  if (!elevation || !elevation->value("slices", nlohmann::json()).is_number_integer() ||
      !elevation->value("min_cos", nlohmann::json()).is_number() ||
      !elevation->value("max_cos", nlohmann::json()).is_number()) {
    throw Error(Error::Kind::InvalidInput, first +
                                               ": not a slice of an elevation stack (no spec.prefilter.elevation "
                                               "with slices, min_cos and max_cos)");
  }
  const int count = (*elevation)["slices"].get<int>();
  stack.minCos = (*elevation)["min_cos"].get<double>();
  stack.maxCos = (*elevation)["max_cos"].get<double>();
  if (count < 2 || count > 64 || !(stack.minCos > 0.0 && stack.minCos <= stack.maxCos && stack.maxCos <= 1.0)) {
    throw Error(Error::Kind::InvalidInput,
                first + ": spec.prefilter.elevation: needs 2 to 64 slices and 0 < min_cos <= max_cos <= 1");
  }
  for (int j = 1; j < count; ++j) {
    const fs::path slicePath = elevationSlicePath(path, j);
    stack.maps.push_back(readMap(slicePath, mipLevel));
    const MapFile& slice = stack.maps.back();
    const nlohmann::json* e = elevationOf(slice);
    if (!e || e->value("slice", -1) != j || e->value("slices", -1) != count ||
        slice.info.parameterization != stack.maps[0].info.parameterization ||
        slice.info.resolution != stack.maps[0].info.resolution) {
      throw Error(Error::Kind::InvalidInput, slicePath.string() + ": not slice " + std::to_string(j) +
                                                 " of the stack " + first + " begins (its metadata or its map differ)");
    }
  }
  return stack;
}

// An image without brdfbake metadata, read as a map of the parameterization options.from says.
MapFile adoptPlainImage(Image image, const fs::path& path, const OpenOutputOptions& options) {
  if (!options.from) {
    throw Error(Error::Kind::InvalidInput, path.string() +
                                               ": not a brdfbake map (no brdfbake metadata); for a plain "
                                               "environment image, give its parameterization (" +
                                               options.fromName + " sphere|paraboloid|cube|latlong)");
  }
  return adoptImage(options.mipLevel == 0 ? std::move(image) : readImage(path, options.mipLevel), *options.from,
                    path.string());
}

// A map whose metadata names a parameterization other than options.from (when given) is refused.
void requireMetadataAgrees(const Image& image, const std::string& parameterization, const fs::path& path,
                           const OpenOutputOptions& options) {
  if (options.from && *options.from != MapInfo::fromJson(image.metadata).parameterization) {
    throw Error(Error::Kind::InvalidArgument, path.string() + ": its metadata says it is a " + parameterization +
                                                  " map, not " + std::string(toString(*options.from)));
  }
}

}  // namespace

std::string_view toString(OutputKind kind) {
  switch (kind) {
    case OutputKind::Map:
      return "map";
    case OutputKind::RadialProfile:
      return "radial_profile";
    case OutputKind::ElevationStack:
      return "elevation_stack";
    case OutputKind::FresnelTable:
      return "fresnel_table";
    case OutputKind::ShIrradiance:
      return "sh_irradiance";
  }
  return "map";
}

BakedOutput BakedOutput::open(const fs::path& path, const OpenOutputOptions& options) {
  require(options.mipLevel >= 0, "mip level must be >= 0");
  BakedOutput out;
  // SH irradiance: a JSON document.
  if (lowerExtension(path) == ".json") {
    const nlohmann::json document = readJsonFile(path);
    requireNoMipLevel(options.mipLevel, path, "an SH irradiance file");
    out.kind_ = OutputKind::ShIrradiance;
    out.sh_ = irradianceShFromJson(document, path.string());
    out.metadata_ = document;
    out.files_ = {path};
    out.indexedByNormal_ = true;
    return out;
  }
  if (!pathExists(path) && cubeFaceSet(path).empty()) {
    if (!isStack(path)) {
      throw Error(Error::Kind::Io, path.string() + ": no such file (nor six cube faces " +
                                       cubeFacePaths(path)[0].filename().string() + " ..., nor an elevation stack " +
                                       elevationSlicePath(path, 0).filename().string() + " ...)");
    }
    StackSlices stack = readStackSlices(path, options.mipLevel);
    out.kind_ = OutputKind::ElevationStack;
    out.maps_ = std::move(stack.maps);
    out.minCos_ = stack.minCos;
    out.maxCos_ = stack.maxCos;
    for (std::size_t j = 0; j < out.maps_.size(); ++j)
      out.files_.push_back(elevationSlicePath(path, static_cast<int>(j)));
  } else if (const auto faces = cubeFaceSet(path); !faces.empty()) {
    out.files_ = faces;
    out.maps_.push_back(readMap(path, options.mipLevel));
  } else {
    out.files_ = {path};
    Image image = readImage(path);
    const std::string parameterization = metadataValue(image.metadata, "parameterization", std::string());
    if (parameterization == "profile") {
      requireNoMipLevel(options.mipLevel, path, "a 1-D radial profile");
      checkProfileImage(image, path);
      out.kind_ = OutputKind::RadialProfile;
      out.radial_ = RadialProfile(axisOf(image.metadata, path), rowTexels(image));
      out.metadata_ = image.metadata;
      out.eyeSpace_ = true;
      return out;
    }
    if (isFresnelTableParameterization(parameterization)) {
      requireNoMipLevel(options.mipLevel, path, "a Fresnel table");
      checkProfileImage(image, path);
      out.kind_ = OutputKind::FresnelTable;
      out.fresnel_ = rowTexels(image);
      out.metadata_ = image.metadata;
      return out;
    }
    if (!hasMapMetadata(image)) {
      out.maps_.push_back(adoptPlainImage(std::move(image), path, options));
      out.metadata_ = out.maps_[0].image.metadata;
      out.eyeSpace_ = *options.from == ParameterizationKind::Sphere;
      return out;
    }
    requireMetadataAgrees(image, parameterization, path, options);
    out.maps_.push_back(readMap(path, options.mipLevel));
  }
  out.metadata_ = out.maps_[0].image.metadata;
  out.indexedByNormal_ = irradianceByNormal(out.maps_[0]);
  out.valueScale_ = irradianceScale(out.maps_[0]);
  out.eyeSpace_ = out.maps_[0].info.parameterization == ParameterizationKind::Sphere;
  return out;
}

BakedOutput BakedOutput::fromMap(Image image, const MapInfo& info) {
  image.metadata = info.toJson();
  BakedOutput out;
  MapFile map;
  map.parameterization = makeParameterization(info.parameterization, info.resolution);
  require(image.width() == map.parameterization->width() && image.height() == map.parameterization->height(),
          "BakedOutput::fromMap: the image's size is not its parameterization's");
  map.info = info;
  map.image = std::move(image);
  out.maps_.push_back(std::move(map));
  out.metadata_ = out.maps_[0].image.metadata;
  out.indexedByNormal_ = irradianceByNormal(out.maps_[0]);
  out.valueScale_ = irradianceScale(out.maps_[0]);
  out.eyeSpace_ = info.parameterization == ParameterizationKind::Sphere;
  return out;
}

Rgba BakedOutput::lookup(const Vec3& direction, std::optional<double> cosView) const {
  if (usesDirection() && !(direction.allFinite() && direction.norm() > 0.0)) {
    throw Error(Error::Kind::InvalidArgument, "the lookup direction must be finite and non-zero");
  }
  switch (kind_) {
    case OutputKind::Map: {
      Rgba v = sampleBilinear(maps_[0].image, *maps_[0].parameterization, direction);
      v.head<3>() *= valueScale_;
      return v;
    }
    case OutputKind::RadialProfile: {
      const Rgb v = radial_->lookup(direction);
      return {v[0], v[1], v[2], 1.0};
    }
    case OutputKind::ElevationStack: {
      // t = clamp(ln(u / min_cos) / ln(max_cos / min_cos), 0, 1); linear in t between neighbouring slices.
      const double u = checkedCosView(cosView, kind_);
      const double range = std::log(maxCos_ / minCos_);
      const double t = range > 1e-12 && u > minCos_ ? std::clamp(std::log(u / minCos_) / range, 0.0, 1.0) : 0.0;
      const int count = static_cast<int>(maps_.size());
      const double x = t * (count - 1);
      const int j = std::min(static_cast<int>(x), count - 2);
      const double f = x - j;
      const MapFile &a = maps_[static_cast<std::size_t>(j)], &b = maps_[static_cast<std::size_t>(j + 1)];
      Rgba v = (1.0 - f) * sampleBilinear(a.image, *a.parameterization, direction) +
               f * sampleBilinear(b.image, *b.parameterization, direction);
      v.head<3>() *= valueScale_;
      return v;
    }
    case OutputKind::FresnelTable: {
      const Rgb v = sampleLinear1d(fresnel_, checkedCosView(cosView, kind_));
      return {v[0], v[1], v[2], 1.0};
    }
    case OutputKind::ShIrradiance: {
      double scratch[9];
      const Rgb v = sh_->evaluate(direction.normalized(), scratch);
      return {v[0], v[1], v[2], 1.0};
    }
  }
  return Rgba::Zero();
}

Rgba BakedOutput::shade(const Vec3& normal, const Vec3& view) const {
  const double cosView = std::clamp(normal.dot(view), 0.0, 1.0);
  const Vec3 r = reflect(view, normal);
  const Vec3 direction = indexedByNormal_ ? normal : (r.norm() > 0.0 ? r : view);
  return lookup(direction, usesCosView() ? std::optional(cosView) : std::nullopt);
}

nlohmann::json BakedOutput::describe() const {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& f : files_) files.push_back(f.string());
  nlohmann::json d = {{"kind", std::string(toString(kind_))}, {"files", files}};
  switch (kind_) {
    case OutputKind::Map:
    case OutputKind::ElevationStack: {
      const MapFile& m = maps_[0];
      d["parameterization"] = std::string(toString(m.info.parameterization));
      d["resolution"] = m.info.resolution;
      d["width"] = m.image.width();
      d["height"] = m.image.height();
      d["indexed_by"] = indexedByNormal_ ? "normal" : "reflected direction";
      if (irradiancePrefilter(m)) {
        d["quantity"] = kIrradianceQuantity;
        if (valueScale_ != 1.0) {
          d["quantity_note"] = "written before brdfbake stated the quantity: the file holds E; lookups divide by pi";
        }
      }
      if (kind_ == OutputKind::Map) {
        d["lookup"] = std::string("bilinear at the ") + (indexedByNormal_ ? "normal n" : "reflected direction r") +
                      " in the map's frame" + (eyeSpace_ ? " (eye space: the view is +z)" : "");
      } else {
        d["slices"] = maps_.size();
        d["min_cos"] = minCos_;
        d["max_cos"] = maxCos_;
        d["lookup"] = "each slice bilinear at the " + std::string(indexedByNormal_ ? "normal" : "reflected direction") +
                      "; t = clamp(ln(n.v / min_cos) / ln(max_cos / min_cos), 0, 1); slice j holds t = j / " +
                      std::to_string(maps_.size() - 1) + "; linear in t between neighbouring slices";
      }
      break;
    }
    case OutputKind::RadialProfile: {
      const Vec3& a = radial_->axis();
      d["resolution"] = radial_->resolution();
      d["axis"] = {a.x(), a.y(), a.z()};
      d["lookup"] =
          "linear in u = |r - axis| / 2, texel i at u = (i + 0.5) / N, clamped (about the view +z: u is the "
          "sphere-map radius)";
      break;
    }
    case OutputKind::FresnelTable:
      d["resolution"] = fresnel_.size();
      d["lookup"] = "F at cos theta = n.v: linear, texel i at (i + 0.5) / N, clamped";
      break;
    case OutputKind::ShIrradiance:
      d["bands"] = sh_->order + 1;
      d["quantity"] = kIrradianceQuantity;
      d["indexed_by"] = "normal";
      d["lookup"] =
          "E(n)/pi = sum_i c_i Y_i(n) at the normal n (radiance-equivalent irradiance; see the file's convention)";
      break;
  }
  d["metadata"] = metadata_;
  return d;
}

BakedOutputFunction::BakedOutputFunction(const BakedOutput& output, std::optional<double> cosView)
    : output_(output), cosView_(cosView) {
  if (output.kind() == OutputKind::FresnelTable) {
    require(!cosView, "a Fresnel table is resampled as seen from +z (n.v from the direction): no fixed n.v");
  } else if (output.usesCosView()) {
    checkedCosView(cosView, output.kind());
  }
}

Rgb BakedOutputFunction::evaluate(const Vec3& direction) const {
  if (output_.kind() == OutputKind::FresnelTable) {
    // The eye-space view +z: n = normalize(d + z), so n.v = sqrt((1 + d.z) / 2).
    const double cosView = std::sqrt(std::clamp((1.0 + direction.normalized().z()) / 2.0, 0.0, 1.0));
    return output_.lookup(direction, cosView).head<3>();
  }
  return output_.lookup(direction, output_.usesCosView() ? cosView_ : std::nullopt).head<3>();
}

}  // namespace brdfbake
