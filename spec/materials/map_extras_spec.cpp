// Map-level extras: "mips" (silhouette mip chain) and "profile_output" (1-D Fresnel texture), parsed
// and written beside the map.
#include <brdfbake/core/files.hpp>
#include <brdfbake/bake/baked_output.hpp>
#include <brdfbake/bake/image_io.hpp>
#include <brdfbake/bake/env_mips.hpp>
#include <brdfbake/bake/mip_chain.hpp>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/core/version.hpp>

#include "registry_entries.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

fs::path profilePath(const MapSpec& map) {
  return map.profileOutput->is_absolute() ? *map.profileOutput : map.output.parent_path() / *map.profileOutput;
}

}  // namespace

namespace materials {

MipLayout parseMipLayout(JsonObjectReader& object, bool mips, const fs::path& output, int resolution) {
  const auto layout = object.optionalString("mip_layout");
  if (!layout || *layout == "files") return MipLayout::Files;
  if (*layout != "tiled") throw specError(object.child("mip_layout"), "must be \"files\" or \"tiled\", got \"" + *layout + "\"");
  if (!mips) throw specError(object.child("mip_layout"), "\"tiled\" lays out mip levels: needs \"mips\": true");
  if (const std::string problem = tiledMipProblem(output, resolution); !problem.empty()) {
    throw specError(object.child("mip_layout"), problem);
  }
  return MipLayout::Tiled;
}


void parseMapExtras(JsonObjectReader& map, MapSpec& spec) {
  const std::string model = spec.modelName();
  if (const auto* mips = map.find("mips")) {
    if (!mips->is_boolean()) throw specError(map.child("mips"), "must be true or false, got " + describe(*mips));
    spec.mips = mips->get<bool>();
    if (spec.mips && model != "silhouette") {
      throw specError(map.child("mips"), "only the silhouette model defines its own mip levels (a ring of constant "
                                         "width in texels); " + model + " has none");
    }
    if (spec.mips && spec.parameterization != ParameterizationKind::Sphere) {
      throw specError(map.child("mips"), "silhouette mip levels are defined for sphere maps only, where the ring is a "
                                         "circle of one width in texels all round");
    }
  }
  spec.mipLayout = parseMipLayout(map, spec.mips, spec.output, spec.resolution);
  if (map.has("profile_output")) {
    const std::string profile = map.string("profile_output");
    if (model != "fresnel") {
      throw specError(map.child("profile_output"), "only the fresnel model has a 1-D profile F(cos theta); " + model +
                                                       " has none");
    }
    if (profile.empty()) throw specError(map.child("profile_output"), "must not be empty");
    try {
      imageFormatFor(profile);
    } catch (const Error& e) {
      throw specError(map.child("profile_output"), e.what());
    }
    spec.profileOutput = fs::path(profile);
    if (sameFile(profilePath(spec), spec.output)) throw specError(map.child("profile_output"), "same file as output");
  }
}

}  // namespace materials

MapWriteReport writeMapExtras(const MapSpec& map, const BakeOptions& bakeOptions, const WriteOptions& writeOptions) {
  MapWriteReport report;
  if (map.mips) {
    const auto* silhouette = dynamic_cast<const SilhouetteMaterial*>(map.material.get());
    require(silhouette != nullptr, map.jsonPath + ": \"mips\" needs a silhouette material");
    BakeOptions options = bakeOptions;
    options.progress = {};
    options.samplesPerTexel = map.samplesPerTexel;
    const std::vector<Image> chain = silhouetteMipChain(*silhouette, map.resolution, options);
    if (map.mipLayout == MipLayout::Tiled) {
      // The whole chain, level 0 included, in the output itself (replacing the single level).
      MapInfo info;
      info.parameterization = ParameterizationKind::Sphere;
      info.resolution = map.resolution;
      info.conventionVersion = kConventionVersion;
      info.spec = map.raw;
      const MapWriteReport written = writeTiledMap(chain, info, map.output, CubeLayout::Cross, writeOptions);
      report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
      report.notes.push_back(map.output.filename().string() + ": " + std::to_string(chain.size()) +
                             " silhouette mip levels in one tiled MIP-mapped OpenEXR");
      return report;
    }
    for (std::size_t level = 1; level < chain.size(); ++level) {
      MapInfo info;
      info.parameterization = ParameterizationKind::Sphere;
      info.resolution = chain[level].width();
      info.conventionVersion = kConventionVersion;
      info.spec = map.raw;
      const MapWriteReport written =
          writeMap(chain[level], info, mipLevelPath(map.output, static_cast<int>(level)), CubeLayout::Cross, writeOptions);
      report.files.insert(report.files.end(), written.files.begin(), written.files.end());
      if (level == 1) report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
    }
  }
  if (map.profileOutput) {
    const auto* fresnel = dynamic_cast<const FresnelMaterial*>(map.material.get());
    require(fresnel != nullptr, map.jsonPath + ": \"profile_output\" needs a fresnel material");
    const std::vector<Rgb> profile = fresnelProfile(fresnel->fresnel(), map.resolution);
    Image image = fresnelProfileImage(profile);
    image.metadata["spec"] = map.raw;
    const fs::path path = profilePath(map);
    const WriteReport written = writeImage(image, path, writeOptions);
    report.files.push_back(path);
    report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
    report.notes.push_back(path.filename().string() + ": 1-D Fresnel profile, texel i holds F at cos theta = (i + 0.5) / " +
                           std::to_string(map.resolution));
  }
  return report;
}

}  // namespace brdfbake
