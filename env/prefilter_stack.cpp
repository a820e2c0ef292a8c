// Prefilter requests that make several maps: elevation stacks of varying lobe models and the
// Fresnel decomposition (prefilter_stack.hpp, docs/prefilter.md).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/output/baked_output.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "prefilter_internal.hpp"

namespace brdfbake {
namespace {
using Clock = std::chrono::steady_clock;

}  // namespace

// ---- glossy mip chains ---------------------------------------------------------------------------

std::vector<double> glossLevelExponents(int count, double scale, double bias) {
  require(count >= 1 && count <= 16, "a gloss chain has 1 to 16 levels, got " + std::to_string(count));
  require(std::isfinite(scale) && std::isfinite(bias), "gloss scale and bias must be finite");
  std::vector<double> exponents;
  for (int k = 0; k < count; ++k) {
    const double glossiness = count == 1 ? 1.0 : std::max(0.0, 1.0 - static_cast<double>(k) / (count - 1));
    const double exponent = std::exp2(scale * glossiness + bias);
    require(exponent >= 0.0 && exponent <= 1e6, "gloss level " + std::to_string(k) + " has Phong exponent " +
                                                    std::to_string(exponent) + ", outside [0, 1e6]");
    exponents.push_back(exponent);
  }
  return exponents;
}

std::vector<double> ggxChainRoughness(int count) {
  require(count >= 1 && count <= 16, "a GGX chain has 1 to 16 levels, got " + std::to_string(count));
  std::vector<double> roughness;
  for (int k = 0; k < count; ++k) roughness.push_back(count == 1 ? 0.0 : static_cast<double>(k) / (count - 1));
  return roughness;
}

std::vector<PrefilterLobe> ggxChainLobes(int count) {
  std::vector<PrefilterLobe> lobes;
  for (double r : ggxChainRoughness(count))
    lobes.push_back(r == 0.0 ? PrefilterLobe::mirror() : PrefilterLobe::ggx(std::max(r, 0.01)));
  return lobes;
}

std::string GlossChain::lobeName() const { return lobe == Lobe::Ggx ? "ggx" : lobe == Lobe::Phong ? "phong" : "blinn"; }

int GlossChain::levelCount(int resolution) const {
  return levels > 0 ? levels : std::min(16, mipLevelCount(resolution));
}

std::vector<PrefilterLobe> GlossChain::lobes(int resolution) const {
  const int count = levelCount(resolution);
  if (lobe == Lobe::Ggx) return ggxChainLobes(count);
  std::vector<PrefilterLobe> out;
  for (double exponent : glossLevelExponents(count, scale, bias))
    out.push_back(lobe == Lobe::Phong ? PrefilterLobe::phong(exponent) : PrefilterLobe::blinn(exponent));
  return out;
}

namespace {
// What "level_values" records about one level of a chain.
nlohmann::json chainLevelValue(const PrefilterLobe& lobe, const PrefilterSummary& s) {
  nlohmann::json value = {{"lobe", lobe.name()},
                          {"method", std::string(toString(s.method))},
                          {"error_estimate", s.errorEstimated ? nlohmann::json(s.errorEstimate) : nlohmann::json()},
                          {"exact", s.exact}};
  if (lobe.kind() == LobeKind::Ggx || lobe.isMirror()) {
    value["roughness"] = lobe.ggxRoughness();
    value["alpha"] = lobe.ggxAlpha();
  } else if (lobe.kind() == LobeKind::Phong) {
    value["exponent"] = lobe.phongExponent();
  }
  return value;
}
}  // namespace

PrefilteredMap prefilterGlossChain(const Environment& environment, const std::vector<PrefilterLobe>& lobes,
                                   const PrefilterOptions& options, const Context& context) {
  options.validate();
  require(!lobes.empty(), "a gloss chain needs at least one level");
  require(!options.mips, "a gloss chain is its own mip chain: turn options.mips off");
  const int count = static_cast<int>(lobes.size());
  require((options.resolution >> (count - 1)) >= 1,
          "a gloss chain of " + std::to_string(count) + " levels needs a resolution of at least " +
              std::to_string(1 << (count - 1)) + ", got " + std::to_string(options.resolution));
  const auto start = Clock::now();
  PrefilteredMap result;
  PrefilterSummary& summary = result.summary;
  summary.maxError = options.maxError;
  std::ostringstream names;
  detail::PrefilterInput input(environment);  // the working pyramid, made once for every level
  for (int k = 0; k < count; ++k) {
    const PrefilterLobe& lobe = lobes[static_cast<std::size_t>(k)];
    require(!lobe.indexedByNormal(), "gloss chain level " + std::to_string(k) + ": irradiance is not a gloss level");
    PrefilterOptions level = options;
    if (lobe.isMirror()) {  // resampling, whatever method the others use
      level.method = PrefilterMethod::Auto;
      level.shOrder = level.importanceSamples = 0;
      level.directTexelsPerWidth = 0.0;
    }
    level.resolution = options.resolution >> k;
    const std::string label = "level " + std::to_string(k) + " (" + lobe.name() + ")";
    PrefilteredMap part;
    try {
      part = prefilter(input, lobe, level,
                       context.part(static_cast<double>(k) / count, static_cast<double>(k + 1) / count));
    } catch (const Error& error) {
      throw Error(error.kind(), label + ": " + error.what());
    }
    if (k == 0) result.map = part.map;
    result.levels.push_back(std::move(part.levels.front()));
    result.levelValues.push_back(chainLevelValue(lobe, part.summary));
    mergePrefilterSummary(summary, part.summary, label, k == 0);
    names << (k ? ", " : "") << lobe.name();
  }
  summary.lobe = lobes.front().name() + " ... " + lobes.back().name();
  summary.detail = "gloss chain: " + names.str();
  summary.levels = count;
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

// ---- elevation stacks ----------------------------------------------------------------------------

std::vector<double> elevationSliceCosines(const LobeModel& model, int count) {
  require(count >= 2, "an elevation stack needs at least 2 slices, got " + std::to_string(count));
  std::vector<double> cosines(static_cast<std::size_t>(count));
  for (int j = 0; j < count; ++j) {
    const double t = static_cast<double>(j) / (count - 1);
    cosines[static_cast<std::size_t>(j)] = j == 0           ? model.minCos
                                           : j == count - 1 ? model.maxCos
                                                            : model.minCos * std::pow(model.maxCos / model.minCos, t);
  }
  return cosines;
}

PrefilteredStack prefilterLobeModelStack(const Environment& environment, const LobeModel& model,
                                         const std::string& name, const PrefilterOptions& options,
                                         const Context& context) {
  model.validate();
  if (!model.variesWithView()) {
    throw Error(Error::Kind::InvalidArgument,
                name +
                    ": a constant lobe model prefilters into one map (prefilterLobeModel); "
                    "stacks over elevation are for lobes that vary with elevation or have a colour profile");
  }
  options.validate();
  const auto start = Clock::now();
  PrefilteredStack stack;
  stack.minCos = model.minCos;
  stack.maxCos = model.maxCos;
  stack.cosines = elevationSliceCosines(model, options.elevations);
  const int count = options.elevations;
  PrefilterSummary& summary = stack.summary;
  summary.lobe = name;
  summary.maxError = options.maxError;
  for (int j = 0; j < count; ++j) {
    const double u = stack.cosines[static_cast<std::size_t>(j)];
    stack.coordinates.push_back(static_cast<double>(j) / (count - 1));
    PrefilterOptions slice = options;
    std::ostringstream label;
    label.precision(4);
    label << "elevation " << j << " (cos " << u << ")";
    try {
      stack.slices.push_back(
          prefilterLobeModel(environment, model.prefilterFormAt(u), name, slice,
                             context.part(static_cast<double>(j) / count, static_cast<double>(j + 1) / count)));
    } catch (const Error& error) {
      throw Error(error.kind(), label.str() + ": " + error.what());
    }
    mergePrefilterSummary(summary, stack.slices.back().summary, label.str(), j == 0);
  }
  std::ostringstream detail;
  detail.precision(4);
  detail << count << " slices over elevation, cos theta " << model.minCos << " to " << model.maxCos
         << " (uniform in t = ln(cos / " << model.minCos << ") / ln(" << model.maxCos << " / " << model.minCos
         << ")) by";
  for (const auto& slice : stack.slices)
    detail << (&slice == &stack.slices.front() ? " " : ", ") << toString(slice.summary.method);
  detail << "; slice 0: " << stack.slices.front().summary.detail;
  summary.detail = detail.str();
  summary.seconds = secondsSince(start);
  return stack;
}

std::filesystem::path elevationSlicePath(const std::filesystem::path& path, int slice) {
  return siblingWithSuffix(path, "_elev" + std::to_string(slice));
}

MapWriteReport writePrefilteredStack(const PrefilteredStack& stack, const std::filesystem::path& path,
                                     nlohmann::json spec, CubeLayout layout, const WriteOptions& options,
                                     MipLayout mipLayout) {
  require(!stack.slices.empty() && stack.slices.size() == stack.cosines.size(),
          "writePrefilteredStack: nothing to write");
  if (!spec.is_object()) spec = nlohmann::json::object();
  if (!spec["prefilter"].is_object()) spec["prefilter"] = nlohmann::json::object();
  const int count = static_cast<int>(stack.slices.size());
  std::ostringstream interpolation;
  interpolation << "t = clamp(ln(n.v / min_cos) / ln(max_cos / min_cos), 0, 1); slice j holds t = j / " << count - 1
                << "; interpolate linearly in t between slices floor(t * " << count - 1 << ") and the next";
  MapWriteReport report;
  for (int j = 0; j < count; ++j) {
    spec["prefilter"]["elevation"] = {{"slice", j},
                                      {"slices", count},
                                      {"cos_theta", stack.cosines[static_cast<std::size_t>(j)]},
                                      {"t", stack.coordinates[static_cast<std::size_t>(j)]},
                                      {"min_cos", stack.minCos},
                                      {"max_cos", stack.maxCos},
                                      {"interpolation", interpolation.str()}};
    const MapWriteReport written = writePrefilteredMap(stack.slices[static_cast<std::size_t>(j)],
                                                       elevationSlicePath(path, j), spec, layout, options, mipLayout);
    report.files.insert(report.files.end(), written.files.begin(), written.files.end());
    if (j == 0) report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
  }
  report.notes.push_back(std::to_string(count) + " elevation slices " +
                         elevationSlicePath(path, 0).filename().string() + " ... " +
                         elevationSlicePath(path, count - 1).filename().string() + ": " + interpolation.str());
  return report;
}

// ---- Fresnel decomposition -----------------------------------------------------------------------

FresnelDecomposition prefilterFresnelDecomposition(const Environment& environment, const PrefilterLobe& specular,
                                                   const FresnelTerm& fresnel, FresnelCombine combine,
                                                   const PrefilterOptions& options, int tableSize,
                                                   const Context& context) {
  if (specular.indexedByNormal()) {
    throw Error(Error::Kind::InvalidArgument,
                "a Fresnel decomposition needs a specular lobe (mirror, phong, blinn, ggx) for "
                "its specular map; the irradiance map is made anyway");
  }
  require(tableSize >= 1 && tableSize <= 65536,
          "the Fresnel table needs 1 to 65536 texels, got " + std::to_string(tableSize));
  options.validate();
  FresnelDecomposition result;
  result.fresnel = fresnel;
  result.combine = combine;
  PrefilterOptions part = options;
  detail::PrefilterInput input(environment);
  result.specular = prefilter(input, specular, part, context.part(0.0, 0.5));
  result.irradiance = prefilter(input, PrefilterLobe::irradiance(), part, context.part(0.5, 1.0));
  result.table = fresnelTable(fresnel, tableSize);
  for (const Rgb& f : result.table) require(f.allFinite(), "the Fresnel table came out non-finite");
  return result;
}

Rgb combineFresnelDecomposition(FresnelCombine combine, const Rgb& fresnel, const Rgb& specular, const Rgb& irradiance,
                                const Rgb& diffuseAlbedo) {
  const Rgb diffuse = diffuseAlbedo * irradiance;  // the irradiance map holds E/pi
  return fresnel * specular + (combine == FresnelCombine::Mix ? (1.0 - fresnel) * diffuse : diffuse);
}

std::filesystem::path fresnelIrradiancePath(const std::filesystem::path& output) {
  return siblingWithSuffix(output, "_irradiance");
}
std::filesystem::path fresnelTablePath(const std::filesystem::path& output) {
  return siblingWithSuffix(output, "_fresnel");
}

namespace {
void addLevels(std::vector<FilePlan::Entry>& out, const std::filesystem::path& file, const PrefilterOutputs& o,
               const std::string& role) {
  const int levels =
      o.mips && o.mipLayout == MipLayout::Files ? (o.mipLevels > 0 ? o.mipLevels : mipLevelCount(o.resolution)) : 1;
  const bool cube = o.parameterization == ParameterizationKind::Cube;
  for (int level = 0; level < levels; ++level) {
    const auto files =
        mapOutputFiles(mipLevelPath(file, level),
                       level == 0 ? role : role + " (mip level " + std::to_string(level) + ")", cube, o.layout);
    out.insert(out.end(), files.begin(), files.end());
  }
}
}  // namespace

std::vector<FilePlan::Entry> prefilterOutputFiles(const std::filesystem::path& output, const PrefilterOutputs& o,
                                                  const std::string& role) {
  std::vector<FilePlan::Entry> out;
  if (o.elevationSlices > 0) {
    for (int j = 0; j < o.elevationSlices; ++j) {
      addLevels(out, elevationSlicePath(output, j), o, role + " (elevation slice " + std::to_string(j) + ")");
    }
    return out;
  }
  addLevels(out, output, o, role);
  if (o.fresnel) {
    addLevels(out, fresnelIrradiancePath(output), o, role + " (Fresnel irradiance map)");
    const auto table = mapOutputFiles(fresnelTablePath(output), role + " (Fresnel table)");
    out.insert(out.end(), table.begin(), table.end());
  }
  return out;
}

MapWriteReport writeFresnelDecomposition(const FresnelDecomposition& decomposition, const std::filesystem::path& output,
                                         nlohmann::json spec, CubeLayout layout, const WriteOptions& options,
                                         MipLayout mipLayout) {
  const int size = static_cast<int>(decomposition.table.size());
  require(size >= 1, "writeFresnelDecomposition: no Fresnel table");
  if (!spec.is_object()) spec = nlohmann::json::object();
  if (!spec["prefilter"].is_object()) spec["prefilter"] = nlohmann::json::object();
  const std::filesystem::path irradiancePath = fresnelIrradiancePath(output), tablePath = fresnelTablePath(output);
  const Rgb f0 = decomposition.fresnel.f0();
  const bool mix = decomposition.combine == FresnelCombine::Mix;
  nlohmann::json fresnel = {
      {"combine", std::string(toString(decomposition.combine))},
      {"formula", mix ? "L = F(n.v) specular(r) + (1 - F(n.v)) k_d irradiance(n), irradiance holding E/pi"
                      : "L = F(n.v) specular(r) + k_d irradiance(n), irradiance holding E/pi"},
      {"specular", output.filename().string()},
      {"irradiance", irradiancePath.filename().string()},
      {"table", tablePath.filename().string()},
      {"table_size", size},
      {"table_texels", "texel i holds F at cos theta = n.v = (i + 0.5) / " + std::to_string(size) +
                           ": a linear lookup at s = n.v returns F"},
      {"f0", {f0[0], f0[1], f0[2]}}};

  // The table first (cheapest to fail), then the two maps.
  Image image = fresnelTableImage(decomposition.table);
  image.metadata["spec"] = spec;
  image.metadata["spec"]["prefilter"]["fresnel"] = fresnel;
  image.metadata["spec"]["prefilter"]["fresnel"]["role"] = "table";
  MapWriteReport report;
  const WriteReport tableWritten = writeImage(image, tablePath, options);
  fresnel["role"] = "specular";
  spec["prefilter"]["fresnel"] = fresnel;
  const MapWriteReport specular = writePrefilteredMap(decomposition.specular, output, spec, layout, options, mipLayout);
  fresnel["role"] = "irradiance";
  spec["prefilter"]["fresnel"] = fresnel;
  const MapWriteReport irradiance =
      writePrefilteredMap(decomposition.irradiance, irradiancePath, spec, layout, options, mipLayout);
  for (const MapWriteReport* part : {&specular, &irradiance}) {
    report.files.insert(report.files.end(), part->files.begin(), part->files.end());
    report.notes.insert(report.notes.end(), part->notes.begin(), part->notes.end());
  }
  report.files.push_back(tablePath);
  report.notes.insert(report.notes.end(), tableWritten.notes.begin(), tableWritten.notes.end());
  report.notes.push_back(tablePath.filename().string() +
                         ": 1-D Fresnel table, texel i holds F at cos theta = (i + 0.5) / " + std::to_string(size) +
                         "; combine " + std::string(toString(decomposition.combine)) + ": " +
                         fresnel["formula"].get<std::string>());
  return report;
}

}  // namespace brdfbake
