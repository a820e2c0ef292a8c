// "measured" materials: a measured table baked as Zimmons & Bastos 1999's mirror-direction reflectance map
// (Zimmons & Bastos 1999 section 8) or through fitted lobes (docs/fitting.md).
//   {"model": "measured", "file": "table.astm", "format": "auto",
//    "method": "mirror", "window_degrees": 10, "rgb": "cie1931" | "single_wavelengths"}
//   {"model": "measured", "file": "table.astm", "method": "fit", "lobes": "auto" | N,
//    "elevation": "auto" | "constant" | "varying", "mode": "reflectance" | "lighting" | "prefiltered"}
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/fit/mirror_direction.hpp>

#include "registry_entries.hpp"

namespace brdfbake::materials {

MeasuredTable tableForBaking(const std::filesystem::path& file, TableFormat format, RgbMethod rgb) {
  MeasuredTable table = readTableForFitting(file, format).toRgb(rgb);
  // A reflectance is never negative: negative measurements (noise around zero) would bake into
  // negative texels, so they are clamped, and the notes say so.
  const auto negatives = (table.values.array() < 0.0).count();
  if (negatives > 0) {
    table.values = table.values.cwiseMax(0.0);
    table.notes.push_back(std::to_string(negatives) + " negative RGB values clamped to 0 for baking");
  }
  return table;
}

FitOptions fitOptionsForBaking(LobeMaterialMode mode) {
  FitOptions options;
  options.estimateHeldOut = false;  // a bake needs the model only (auto choices still estimate it)
  options.halfDifference = mode != LobeMaterialMode::Prefiltered;  // a half-difference table has no prefiltered form
  return options;
}

std::shared_ptr<const Material> parseMeasured(JsonObjectReader& m, const MaterialContext& context) {
  const std::filesystem::path file = resolveMaterialFile(m, context);
  const TableFormat format = m.parsed("format", parseTableFormat, "auto");
  const std::string method = m.string("method");
  if (method != "mirror" && method != "fit")
    throw specError(m.child("method"), "must be \"mirror\" or \"fit\", got \"" + printable(method, 40) + "\"");
  const std::string rgbName = m.optionalString("rgb").value_or("cie1931");
  RgbMethod rgb = RgbMethod::Cie1931;
  if (rgbName == "single_wavelengths")
    rgb = RgbMethod::SingleWavelengths;
  else if (rgbName != "cie1931")
    throw specError(m.child("rgb"),
                    "must be \"cie1931\" or \"single_wavelengths\", got \"" + printable(rgbName, 40) + "\"");

  if (context.underEnvironment && method == "mirror") {
    throw specError(m.child("method"),
                    "a material lit by an environment needs a BRDF over every light direction; the mirror-direction "
                    "table holds the mirror direction only. Use \"fit\" (lobes fitted to the whole table; brdfbake "
                    "fit reports their held-out error). The table itself is not used directly: its incident angles "
                    "are 10 degrees apart and it has no sample on the mirror direction, so a nearest-angle lookup "
                    "would band the map and miss sharp highlights");
  }
  // Options of the other method are mistakes, not silently ignored.
  const std::vector<std::string> mirrorOnly{"window_degrees"}, fitOnly{"lobes", "elevation", "mode"};
  for (const auto& key : method == "mirror" ? fitOnly : mirrorOnly) {
    if (m.has(key))
      throw specError(m.child(key),
                      "only applies with \"method\": \"" + std::string(method == "mirror" ? "fit" : "mirror") + "\"");
  }
  double window = 10.0;
  FitOptions options;
  LobeMaterialMode mode = LobeMaterialMode::Reflectance;
  if (method == "mirror") {
    window = m.number("window_degrees", 10.0, 0.0, 180.0, /*exclusiveMinimum=*/true);
  } else {
    if (const auto* lobes = m.find("lobes")) {
      if (lobes->is_string() && lobes->get<std::string>() == "auto") {
        options.lobes = 0;
      } else {
        options.lobes = m.integer("lobes", 1, kMaxFitLobes);
      }
    }
    options.elevation = m.parsed("elevation", parseElevationChoice, "auto");
    // Varying lobes are the per-channel method's (the shared one fits constant Lafortune lobes).
    if (options.elevation == ElevationChoice::Varying) options.method = FitMethod::PerChannel;
    mode = parseLobeMode(m, context.underEnvironment);
    const FitOptions baking = fitOptionsForBaking(mode);
    options.estimateHeldOut = baking.estimateHeldOut;
    options.halfDifference = baking.halfDifference;
  }

  MeasuredTable table;
  try {
    table = tableForBaking(file, format, rgb);
  } catch (const Error& e) {
    throw specError(m.child("file"), e.what());
  }
  if (context.notes) {
    for (const auto& note : table.notes) context.notes->push_back(m.child("file") + ": " + note);
  }
  if (method == "mirror") {
    return std::make_shared<MirrorDirectionMaterial>(strongestNearMirrorTable(table, radians(window)), "measured");
  }
  DeferredFit fit{std::move(table), options, mode, m.path()};
  if (context.deferredFit) {
    *context.deferredFit = std::move(fit);
    return nullptr;
  }
  return fit.run();
}

}  // namespace brdfbake::materials

namespace brdfbake {

std::shared_ptr<const Material> DeferredFit::run(const Context& context) const {
  FitResult fit;
  try {
    fit = fitLobes(table, options, context);
  } catch (const Error& e) {
    throw specError(jsonPath + ".file", e.what());
  }
  if (!fit.usable())
    throw specError(jsonPath + ".file", "the lobe fit did not converge to a usable result:\n" + fit.briefReport());
  return std::make_shared<LobeMaterial>(std::move(fit.model), mode, "measured");
}

}  // namespace brdfbake
