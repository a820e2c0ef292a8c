// Map-level extras: "mips" (silhouette mip chain) and "fresnel_table_output" (1-D Fresnel table), parsed
// and written beside the map.
#include <brdfbake/bake/baked_mips.hpp>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include "registry_entries.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

fs::path fresnelTablePath(const MapSpec& map) {
  const fs::path& table = *map.materialMap()->fresnelTableOutput;
  return table.is_absolute() ? table : map.output.parent_path() / table;
}

// The key naming the Fresnel table's file: "fresnel_table_output", or "profile_output", its former
// name (still read, so existing specs keep working); nullopt when neither is given.
std::optional<std::string> fresnelTableKey(JsonObjectReader& map) {
  const bool current = map.has("fresnel_table_output"), former = map.has("profile_output");
  if (current && former) {
    throw specError(map.child("profile_output"), "the former name of \"fresnel_table_output\": give one of the two");
  }
  if (current) return "fresnel_table_output";
  if (former) return "profile_output";
  return std::nullopt;
}

}  // namespace

namespace materials {

MipLayout parseMipLayout(JsonObjectReader& object, bool mips, const fs::path& output, int resolution) {
  const auto layout = object.optionalString("mip_layout");
  if (!layout || *layout == "files") return MipLayout::Files;
  if (*layout != "tiled")
    throw specError(object.child("mip_layout"),
                    "must be \"files\" or \"tiled\", got \"" + printable(*layout, 40) + "\"");
  if (!mips) throw specError(object.child("mip_layout"), "\"tiled\" lays out mip levels: needs \"mips\": true");
  if (const std::string problem = tiledMipProblem(output, resolution); !problem.empty()) {
    throw specError(object.child("mip_layout"), problem);
  }
  return MipLayout::Tiled;
}

void parseMapExtras(JsonObjectReader& map, MapSpec& spec) {
  MaterialMapSpec& m = *spec.materialMap();
  const std::string model = m.modelName();
  if (map.has("mips")) {
    m.mips = map.boolean("mips");
    if (m.mips && model != "silhouette") {
      throw specError(map.child("mips"),
                      "only the silhouette model defines its own mip levels (a ring of constant "
                      "width in texels); " +
                          model + " has none");
    }
    if (m.mips && spec.parameterization != ParameterizationKind::Sphere) {
      throw specError(map.child("mips"),
                      "silhouette mip levels are defined for sphere maps only, where the ring is a "
                      "circle of one width in texels all round");
    }
  }
  m.mipLayout = parseMipLayout(map, m.mips, spec.output, spec.resolution);
  if (const auto key = fresnelTableKey(map)) {
    const std::string file = map.string(*key);
    if (model != "fresnel") {
      throw specError(map.child(*key), "only the fresnel model has a 1-D table F(cos theta); " + model + " has none");
    }
    if (file.empty()) throw specError(map.child(*key), "must not be empty");
    try {
      imageFormatFor(file);
    } catch (const Error& e) {
      throw specError(map.child(*key), e.what());
    }
    m.fresnelTableOutput = fs::path(file);
    if (sameFile(fresnelTablePath(spec), spec.output)) throw specError(map.child(*key), "same file as output");
  }
}

}  // namespace materials

MapWriteReport writeMapExtras(const MapSpec& map, const BakeOptions& bakeOptions, const WriteOptions& writeOptions,
                              const Context& context) {
  MapWriteReport report;
  const MaterialMapSpec* m = map.materialMap();
  if (!m) return report;  // an environment map's extras are written with it (writeFresnelDecomposition, mips)
  if (m->mips) {
    const auto* silhouette = dynamic_cast<const SilhouetteMaterial*>(m->material.get());
    require(silhouette != nullptr, map.jsonPath + ": \"mips\" needs a silhouette material");
    BakeOptions options = bakeOptions;
    options.samplesPerTexel = map.samplesPerTexel;
    const std::vector<Image> chain =
        silhouetteMipChain(*silhouette, map.resolution, options, context.withoutProgress());
    if (m->mipLayout == MipLayout::Tiled) {
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
      const MapWriteReport written = writeMap(chain[level], info, mipLevelPath(map.output, static_cast<int>(level)),
                                              CubeLayout::Cross, writeOptions);
      report.files.insert(report.files.end(), written.files.begin(), written.files.end());
      if (level == 1) report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
    }
  }
  if (m->fresnelTableOutput) {
    const auto* fresnel = dynamic_cast<const FresnelMaterial*>(m->material.get());
    require(fresnel != nullptr, map.jsonPath + ": \"fresnel_table_output\" needs a fresnel material");
    Image image = fresnelTableImage(fresnelTable(fresnel->fresnel(), map.resolution));
    image.metadata["spec"] = map.raw;
    const fs::path path = fresnelTablePath(map);
    const WriteReport written = writeImage(image, path, writeOptions);
    report.files.push_back(path);
    report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
    report.notes.push_back(path.filename().string() +
                           ": 1-D Fresnel table, texel i holds F at cos theta = (i + 0.5) / " +
                           std::to_string(map.resolution));
  }
  return report;
}

}  // namespace brdfbake
