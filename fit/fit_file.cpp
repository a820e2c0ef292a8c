#include <brdfbake/core/error.hpp>
#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_reader.hpp>
#include <brdfbake/io/json_text.hpp>

#include <fstream>
#include <optional>
#include <random>
#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

// Every number written goes through here: a fit file never holds NaN or infinity.
double finite(double value, const char* what) {
  if (!std::isfinite(value)) throw Error(Error::Kind::Numerical, std::string("fit file: ") + what + " is not finite");
  return value;
}

nlohmann::ordered_json numbers(const std::vector<double>& values, const char* what) {
  nlohmann::ordered_json array = nlohmann::ordered_json::array();
  for (double v : values) array.push_back(finite(v, what));
  return array;
}

std::string requestedLobes(int lobes) { return lobes == 0 ? "auto" : std::to_string(lobes); }

std::vector<double> readNumbers(JsonObjectReader& reader, const std::string& key, std::size_t count, double minimum,
                                double maximum) {
  const auto& array = reader.array(key);
  const std::string path = reader.child(key);
  if (array.size() != count) {
    throw specError(path, "must hold " + std::to_string(count) + " number(s), got " + std::to_string(array.size()));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < array.size(); ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const double v = JsonObjectReader::asNumber(array[i], at);
    if (v < minimum) throw specError(at, "must be >= " + describe(minimum) + ", got " + describe(v));
    if (v > maximum) throw specError(at, "must be <= " + describe(maximum) + ", got " + describe(v));
    values.push_back(v);
  }
  return values;
}

ChannelFitStats readStats(JsonObjectReader stats, const std::string& name) {
  ChannelFitStats s;
  s.name = name;
  s.samples = static_cast<std::size_t>(stats.integer("samples", 0, 1 << 30));
  s.rmsCosineWeighted = stats.number("rms_cosine_weighted", 0.0);
  s.logRmse = stats.number("log_rmse", 0.0);
  s.cubeRootRmse = stats.number("cube_root_rmse", 0.0);
  JsonObjectReader worst = stats.object("worst_sample");
  s.worst.index = static_cast<std::size_t>(worst.integer("index", 0, 1 << 30));
  s.worst.angles = {worst.number("theta_i"), worst.number("phi_i"), worst.number("theta_s"), worst.number("phi_s")};
  s.worst.measured = worst.number("measured");
  s.worst.fitted = worst.number("fitted");
  worst.finish();
  s.solver.iterations = stats.integer("iterations", 0, 1 << 30);
  s.totalIterations = stats.integer("total_iterations", 0, 1 << 30);
  s.seconds = stats.number("seconds", 0.0);
  s.solver.termination = stats.string("termination");
  s.solver.usable = stats.boolean("usable");
  s.solver.briefReport = stats.optionalString("brief_report").value_or("");
  stats.finish();
  return s;
}

nlohmann::ordered_json splitToJson(const HeldOutSplit& split) {
  nlohmann::ordered_json json = {{"name", split.name},
                                 {"elevation_deg", finite(split.elevationDegrees, "elevation")},
                                 {"held_rows", split.heldRows},
                                 {"log_error", finite(split.error, "held-out error")},
                                 {"lambert_log_error", finite(split.lambertError, "Lambert error")},
                                 {"ratio_to_lambert", finite(split.ratio(), "held-out ratio")}};
  if (split.largestRowShare > 0.0) {  // none when the fit's error is 0
    const SampleAngles& row = split.largestRow;
    json["largest_row"] = {{"share", finite(split.largestRowShare, "largest row's share")},
                           {"lambert_share", finite(split.largestRowLambertShare, "largest row's share")},
                           {"theta_i", finite(row.thetaIn, "angle")},
                           {"phi_i", finite(row.phiIn, "angle")},
                           {"theta_s", finite(row.thetaOut, "angle")},
                           {"phi_s", finite(row.phiOut, "angle")},
                           {"mirror_offset_deg", finite(split.largestRowMirrorOffset, "angle")},
                           {"ratio_without", finite(split.ratioWithoutLargestRow(), "held-out ratio")}};
  }
  return json;
}

HeldOutSplit splitFromJson(JsonObjectReader r) {
  HeldOutSplit split;
  split.name = r.string("name");
  split.elevationDegrees = r.number("elevation_deg", 0.0, 90.0);
  split.heldRows = static_cast<std::size_t>(r.integer("held_rows", 0, 1 << 30));
  split.error = r.number("log_error", 0.0);
  split.lambertError = r.number("lambert_log_error", 0.0);
  r.number("ratio_to_lambert", 0.0);  // recomputed
  if (r.has("largest_row")) {         // absent when the fit's error is 0, and in files written before it
    JsonObjectReader row = r.object("largest_row");
    split.largestRowShare = row.number("share", 0.0, 1.0);
    split.largestRowLambertShare = row.number("lambert_share", 0.0, 1.0);
    split.largestRow = {row.number("theta_i", 0.0, kPi / 2), row.number("phi_i"), row.number("theta_s", 0.0, kPi / 2),
                        row.number("phi_s")};
    split.largestRowMirrorOffset = row.number("mirror_offset_deg", 0.0, 180.0);
    row.number("ratio_without", 0.0);  // recomputed
    row.finish();
  }
  r.finish();
  return split;
}

nlohmann::ordered_json heldOutToJson(const HeldOutReport& report) {
  nlohmann::ordered_json elevations = nlohmann::ordered_json::array();
  for (const auto& e : report.elevations) elevations.push_back(splitToJson(e));
  return {{"error",
           "sqrt(mean over held-out samples and channels of (ln(1 + cos theta_i f_fit) - ln(1 + cos theta_i "
           "f_measured))^2)"},
          {"kfold", splitToJson(report.kfold)},
          {"elevations", elevations},
          {"score", finite(report.score(), "held-out score")},
          {"seconds", finite(report.seconds, "seconds")}};
}

HeldOutReport heldOutFromJson(JsonObjectReader r) {
  HeldOutReport report;
  r.optionalString("error");
  report.kfold = splitFromJson(r.object("kfold"));
  const auto& elevations = r.array("elevations");
  for (std::size_t i = 0; i < elevations.size(); ++i) {
    report.elevations.push_back(
        splitFromJson(JsonObjectReader(elevations[i], r.child("elevations") + "[" + std::to_string(i) + "]")));
  }
  r.number("score", 0.0);  // recomputed
  report.seconds = r.number("seconds", 0.0);
  r.finish();
  return report;
}

nlohmann::ordered_json sourceToJson(const FitSource& source) {
  return {{"file", source.file},
          {"format", source.format},
          {"samples", source.samples},
          {"channels", source.channels},
          {"notes", source.notes}};
}

// "model": the formula, the elevation and its range, the lobe count, the wavelengths of spectral channels.
nlohmann::ordered_json modelToJson(const LobeModel& model) {
  const std::size_t lobes = model.channels.empty() ? 0 : model.channels[0].lobes.size();
  nlohmann::ordered_json m = {
      {"description", lobeModelDescription(model.elevation, model.colorProfile)},
      {"elevation", std::string(toString(model.elevation))},
      {"elevation_range", {{"min_cos", finite(model.minCos, "min_cos")}, {"max_cos", finite(model.maxCos, "max_cos")}}},
      {"lobes", lobes}};
  if (!model.wavelengthsNm.empty()) m["wavelengths_nm"] = numbers(model.wavelengthsNm, "wavelength");
  if (model.colorProfile != ColorProfile::None) m["color_profile"] = std::string(toString(model.colorProfile));
  if (model.hasHalfDifference()) {
    m["description"] = halfDifferenceTableDescription();
    m["half_difference"] = {{"half_angle_knots", model.halfDifference.halfAngleKnots},
                            {"difference_degree", model.halfDifference.differenceDegree}};
  }
  return m;
}

nlohmann::ordered_json candidateToJson(const ModelCandidate& c) {
  return {{"lobes", c.lobes},
          {"elevation", std::string(toString(c.elevation))},
          {"kind", std::string(toString(c.kind))},
          {"parameters", c.parameters},
          {"held_out_score", finite(c.heldOutScore, "held-out score")},
          {"kfold_ratio", finite(c.kfoldRatio, "k-fold ratio")},
          {"elevation_ratio", finite(c.elevationRatio, "elevation ratio")},
          {"seconds", finite(c.seconds, "seconds")},
          {"max_exponent", finite(c.maxExponent, "max exponent")},
          {"varying_prior", finite(c.varyingPrior, "varying prior")},
          {"color_profile", std::string(toString(c.colorProfile))},
          {"refined", c.refined},
          {"chosen", c.chosen}};
}

// "fit": how the model was fitted (the options), the candidates tried and the held-out estimate.
nlohmann::ordered_json fitSectionToJson(const FitResult& fit) {
  const FitOptions& o = fit.options;
  nlohmann::ordered_json candidates = nlohmann::ordered_json::array();
  for (const auto& c : fit.candidates) candidates.push_back(candidateToJson(c));
  const bool perChannel = o.method == FitMethod::PerChannel;
  nlohmann::ordered_json section = {
      {"method", std::string(toString(o.method))},
      {"residual", perChannel ? "cbrt(cos theta_i f_fit + eps) - cbrt(cos theta_i f_measured + eps), "
                                "eps = 1e-6 of the channel's largest cos theta_i f"
                              : "ln(1 + cos theta_i f_fit) - ln(1 + cos theta_i max(f_measured, 0))"},
      {"kind", std::string(toString(o.kind))},
      {"max_exponent", finite(o.maxExponent, "max exponent")},
      {"varying_prior", finite(o.varyingPrior, "varying prior")},
      {"loss", std::string(toString(o.loss))},
      {"loss_scale", finite(o.lossScale, "loss scale")},
      {"auto_margin", finite(o.autoMargin, "auto margin")},
      {"color_profile_margin", finite(o.colorProfileMargin, "colour profile margin")},
      {"refine_candidates", o.refineCandidates},
      {"half_difference", o.halfDifference},
      {"elevation_margin", finite(o.elevationMargin, "elevation margin")},
      {"requested_lobes", requestedLobes(o.lobes)},
      {"requested_elevation", std::string(toString(o.elevation))},
      {"requested_color_profile", std::string(toString(o.colorProfile))},
      {"seconds", finite(fit.seconds, "seconds")},
      {"usable", fit.usable()},
      {"in_sample_log_error", finite(fit.inSampleError, "in-sample error")},
      {"candidates", candidates}};
  if (fit.heldOut) section["held_out"] = heldOutToJson(*fit.heldOut);
  if (const ModelCandidate* radial = fit.bestRadiallySymmetric()) {
    section["best_radially_symmetric"] = candidateToJson(*radial);
    section["best_radially_symmetric"].erase("chosen");
  }
  return section;
}

nlohmann::ordered_json lobeToJson(const Lobe& lobe) {
  nlohmann::ordered_json entry = {{"weight", numbers(lobe.weight, "lobe weight")},
                                  {"exponent", numbers(lobe.exponent, "lobe exponent")}};
  if (lobe.halfVector) {
    entry["axis"] = "half_vector";
    entry["fresnel"] = finite(lobe.fresnel, "lobe fresnel");
  } else if (!lobe.aboutMirror()) {
    entry["cxy"] = finite(lobe.cxy, "lobe cxy");
  }
  if (!lobe.weightProfile.empty()) entry["weight_profile"] = numbers(lobe.weightProfile, "colour profile");
  if (!lobe.fresnelProfile.empty()) entry["fresnel_profile"] = numbers(lobe.fresnelProfile, "colour profile");
  return entry;
}

nlohmann::ordered_json statsToJson(const ChannelFitStats& s) {
  return {{"samples", s.samples},
          {"rms_cosine_weighted", finite(s.rmsCosineWeighted, "rms")},
          {"log_rmse", finite(s.logRmse, "log rmse")},
          {"cube_root_rmse", finite(s.cubeRootRmse, "cube-root rmse")},
          {"worst_sample",
           {{"index", s.worst.index},
            {"theta_i", finite(s.worst.angles.thetaIn, "angle")},
            {"phi_i", finite(s.worst.angles.phiIn, "angle")},
            {"theta_s", finite(s.worst.angles.thetaOut, "angle")},
            {"phi_s", finite(s.worst.angles.phiOut, "angle")},
            {"measured", finite(s.worst.measured, "measured value")},
            {"fitted", finite(s.worst.fitted, "fitted value")}}},
          {"iterations", s.solver.iterations},
          {"total_iterations", s.totalIterations},
          {"seconds", finite(s.seconds, "seconds")},
          {"termination", s.solver.termination},
          {"usable", s.solver.usable},
          {"brief_report", s.solver.briefReport}};
}

// One entry of "channels"; `stats` (the fit's statistics of the channel) may be null.
nlohmann::ordered_json channelToJson(const LobeChannel& channel, const ChannelFitStats* stats) {
  nlohmann::ordered_json lobeArray = nlohmann::ordered_json::array();
  for (const auto& lobe : channel.lobes) lobeArray.push_back(lobeToJson(lobe));
  nlohmann::ordered_json entry = {
      {"name", channel.name}, {"diffuse", finite(channel.diffuse, "diffuse")}, {"lobes", lobeArray}};
  if (!channel.diffuseProfile.empty()) entry["diffuse_profile"] = numbers(channel.diffuseProfile, "colour profile");
  if (!channel.halfDifferenceCoefficients.empty())
    entry["half_difference"] = numbers(channel.halfDifferenceCoefficients, "half-difference coefficient");
  if (stats) entry["stats"] = statsToJson(*stats);
  return entry;
}

void readFormatAndVersion(JsonObjectReader& root) {
  const std::string format = root.string("format");
  if (format != kFitFileFormat) {
    throw specError("format", "must be \"" + std::string(kFitFileFormat) + "\", got \"" + printable(format, 60) + "\"");
  }
  const int version = root.integer("version", 1, 1 << 20);
  if (version != kFitFileVersion) {
    throw specError("version", "this brdfbake reads version " + std::to_string(kFitFileVersion) +
                                   ", the file is version " + std::to_string(version));
  }
  root.optionalString("generator");
}

void readSource(JsonObjectReader source, FitSource& out) {
  out.file = source.string("file");
  out.format = source.string("format");
  out.samples = static_cast<std::size_t>(source.integer("samples", 0, 1 << 30));
  out.channels = source.string("channels");
  const auto& notes = source.array("notes");
  for (std::size_t i = 0; i < notes.size(); ++i) {
    if (!notes[i].is_string())
      throw specError(source.child("notes") + "[" + std::to_string(i) + "]", "must be a string");
    out.notes.push_back(notes[i].get<std::string>());
  }
  source.finish();
}

// "model": the elevation, its range and the wavelengths into `model`; returns the lobe count.
int readModelShape(JsonObjectReader m, LobeModel& model) {
  m.optionalString("description");
  model.elevation = m.parsed("elevation", parseLobeElevation);
  JsonObjectReader range = m.object("elevation_range");
  model.minCos = range.number("min_cos", 0.0, 1.0, /*exclusiveMinimum=*/true);
  model.maxCos = range.number("max_cos", model.minCos, 1.0);
  range.finish();
  const int lobeCount = m.integer("lobes", 0, kMaxModelLobes);
  if (m.has("wavelengths_nm")) {
    const auto& w = m.array("wavelengths_nm");
    for (std::size_t i = 0; i < w.size(); ++i) {
      const std::string at = m.child("wavelengths_nm") + "[" + std::to_string(i) + "]";
      model.wavelengthsNm.push_back(JsonObjectReader::asNumber(w[i], at));
      if (i > 0 && !(model.wavelengthsNm[i] > model.wavelengthsNm[i - 1]))
        throw specError(at, "wavelengths must increase");
    }
  }
  if (m.has("color_profile")) model.colorProfile = m.parsed("color_profile", parseColorProfile);
  if (m.has("half_difference")) {
    JsonObjectReader table = m.object("half_difference");
    model.halfDifference.halfAngleKnots = table.integer("half_angle_knots", 2, 64);
    model.halfDifference.differenceDegree = table.integer("difference_degree", 0, kMaxTableDegree);
    table.finish();
  }
  m.finish();
  return lobeCount;
}

// "requested_lobes": "auto" (0) or a positive whole number.
int readRequestedLobes(JsonObjectReader& fit) {
  const std::string lobes = fit.string("requested_lobes");
  if (lobes == "auto") return 0;
  const std::optional<int> count = wholeNumberIn(lobes);
  if (count && *count >= 1) return *count;
  throw specError(fit.child("requested_lobes"),
                  "must be \"auto\" or a positive whole number, got \"" + printable(lobes, 40) + "\"");
}

// One of "fit.candidates". `fitHasMethod`: false in files written before held-out selection, whose
// candidates are {"lobes", "elevation", "error" (in-sample), "chosen"}.
ModelCandidate readCandidate(JsonObjectReader c, bool fitHasMethod) {
  ModelCandidate candidate;
  candidate.lobes = c.integer("lobes", fitHasMethod ? 0 : 1, kMaxModelLobes);  // 0: a half-difference table
  candidate.elevation = c.parsed("elevation", parseLobeElevation);
  if (!fitHasMethod) {
    c.number("error", 0.0);
  } else {
    const std::string kind = c.string("kind");
    if (kind != "mirror" && kind != "lafortune" && kind != "half_vector" && kind != "mixed" &&
        kind != "half_difference") {
      throw specError(c.child("kind"),
                      "must be \"mirror\", \"lafortune\", \"half_vector\", \"mixed\" or \"half_difference\", got \"" +
                          printable(kind, 40) + "\"");
    }
    candidate.kind = parseLobeKindChoice(kind);
    if ((candidate.kind == LobeKindChoice::HalfDifference) != (candidate.lobes == 0))
      throw specError(c.child("lobes"), "must be 0 for a half-difference table and at least 1 for lobes");
    candidate.parameters = c.integer("parameters", 0, 1 << 30);
    candidate.heldOutScore = c.number("held_out_score", 0.0);
    candidate.kfoldRatio = c.number("kfold_ratio", 0.0);
    candidate.elevationRatio = c.number("elevation_ratio", 0.0);
    candidate.seconds = c.number("seconds", 0.0);
    if (c.has("max_exponent")) candidate.maxExponent = c.number("max_exponent", 0.0, kMaxLobeExponent);
    if (c.has("varying_prior")) candidate.varyingPrior = c.number("varying_prior", 0.0);
    if (c.has("color_profile")) candidate.colorProfile = c.parsed("color_profile", parseColorProfile);
    candidate.refined = c.boolean("refined", true);
  }
  candidate.chosen = c.boolean("chosen");
  c.finish();
  return candidate;
}

// "fit": the options the model was fitted with, the held-out estimate and the candidates.
void readFitSection(JsonObjectReader fit, FitResult& result) {
  fit.optionalString("residual");
  FitOptions& o = result.options;
  const bool fitHasMethod = fit.has("method");
  if (fitHasMethod) {
    o.method = fit.parsed("method", parseFitMethod);
  } else {
    o.method = FitMethod::PerChannel;  // files written before the shared method
  }
  if (fit.has("kind")) {
    o.kind = fit.parsed("kind", parseLobeKindChoice);
  }
  if (fit.has("max_exponent")) o.maxExponent = fit.number("max_exponent", kMinLobeExponent, kMaxLobeExponent);
  if (fit.has("varying_prior")) o.varyingPrior = fit.number("varying_prior", 0.0);
  if (fit.has("in_sample_log_error")) result.inSampleError = fit.number("in_sample_log_error", 0.0);
  if (fit.has("held_out")) result.heldOut = heldOutFromJson(fit.object("held_out"));
  if (fit.has("best_radially_symmetric")) fit.object("best_radially_symmetric");  // derived from the candidates
  o.loss = fit.parsed("loss", parseRobustLoss);
  o.lossScale = fit.number("loss_scale", 0.0, HUGE_VAL, true);
  o.autoMargin = fit.number("auto_margin", 0.0, 1.0, true);
  if (fit.has("color_profile_margin")) o.colorProfileMargin = fit.number("color_profile_margin", 0.0, 1.0, true);
  o.refineCandidates = fit.boolean("refine_candidates", false);
  o.halfDifference = fit.boolean("half_difference", false);  // files written before it: not tried
  o.elevationMargin = fit.number("elevation_margin", 0.0, 1.0, true);
  o.lobes = readRequestedLobes(fit);
  o.elevation = fit.parsed("requested_elevation", parseElevationChoice);
  if (fit.has("requested_color_profile"))
    o.colorProfile = fit.parsed("requested_color_profile", parseColorProfileChoice);
  result.seconds = fit.number("seconds", 0.0);
  fit.require("usable");  // recomputed from the channels' stats
  const auto& candidates = fit.array("candidates");
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    result.candidates.push_back(readCandidate(
        JsonObjectReader(candidates[i], fit.child("candidates") + "[" + std::to_string(i) + "]"), fitHasMethod));
  }
  fit.finish();
}

// A colour profile (brdf/lobes.hpp): kColorProfileCount numbers >= 0, or empty when `key` is absent
// (LobeModel::validate then checks that the model's colour profile asks for it).
std::vector<double> readColorProfile(JsonObjectReader& reader, const std::string& key) {
  if (!reader.has(key)) return {};
  return readNumbers(reader, key, kColorProfileCount, 0.0, kMaxLobeWeight);
}

// One lobe of a channel, `count` coefficients per weight and exponent.
Lobe readLobe(JsonObjectReader lobe, std::size_t count) {
  Lobe l;
  l.weight = readNumbers(lobe, "weight", count, count == 1 ? 0.0 : 1e-300, kMaxLobeWeight);
  l.exponent = readNumbers(lobe, "exponent", count, kMinLobeExponent, kMaxLobeExponent);
  const std::string axis = lobe.optionalString("axis").value_or("lafortune");
  if (axis == "half_vector") {
    l.halfVector = true;
    l.fresnel = lobe.number("fresnel", 0.0, 0.0, kMaxLobeWeight, false);
  } else if (axis == "lafortune") {
    l.cxy = lobe.number("cxy", -1.0, -kMaxLobeCxy, kMaxLobeCxy, false);
  } else {
    throw specError(lobe.child("axis"),
                    "must be \"lafortune\" (the default) or \"half_vector\", got \"" + printable(axis, 40) + "\"");
  }
  l.weightProfile = readColorProfile(lobe, "weight_profile");
  l.fresnelProfile = readColorProfile(lobe, "fresnel_profile");
  lobe.finish();
  return l;
}

// One entry of "channels": its `lobeCount` lobes of `count` coefficients, its `tableCount` table
// coefficients (none without a table) and, if present, its stats.
LobeChannel readChannel(JsonObjectReader ch, int lobeCount, std::size_t count, std::size_t tableCount,
                        std::optional<ChannelFitStats>& stats) {
  LobeChannel channel;
  channel.name = ch.string("name");
  channel.diffuse = ch.number("diffuse", 0.0, kMaxLobeWeight);
  channel.diffuseProfile = readColorProfile(ch, "diffuse_profile");
  if (tableCount > 0)
    channel.halfDifferenceCoefficients =
        readNumbers(ch, "half_difference", tableCount, -kMaxTableLogValue, kMaxTableLogValue);
  else if (ch.has("half_difference"))
    throw specError(ch.child("half_difference"),
                    "coefficients of a half-difference table the model has not (model.half_difference)");
  const auto& lobes = ch.array("lobes");
  if (static_cast<int>(lobes.size()) != lobeCount) {
    throw specError(ch.child("lobes"), "model.lobes says " + std::to_string(lobeCount) + " lobe(s), this channel has " +
                                           std::to_string(lobes.size()));
  }
  for (std::size_t k = 0; k < lobes.size(); ++k) {
    channel.lobes.push_back(
        readLobe(JsonObjectReader(lobes[k], ch.child("lobes") + "[" + std::to_string(k) + "]"), count));
  }
  if (ch.has("stats")) stats = readStats(ch.object("stats"), channel.name);
  ch.finish();
  return channel;
}

// "channels" into fit.model (whose elevation and wavelengths are read) and, when every channel has
// them, their stats into fit.channels.
void readChannels(JsonObjectReader& root, int lobeCount, FitResult& fit) {
  LobeModel& model = fit.model;
  const auto& channels = root.array("channels");
  if (channels.empty()) throw specError("channels", "must hold at least one channel");
  const std::size_t count = static_cast<std::size_t>(elevationCoefficientCount(model.elevation));
  const std::size_t tableCount =
      model.hasHalfDifference() ? static_cast<std::size_t>(model.halfDifference.coefficientCount()) : 0;
  bool allStats = true, anyStats = false;
  std::vector<ChannelFitStats> stats;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    std::optional<ChannelFitStats> channelStats;
    model.channels.push_back(readChannel(JsonObjectReader(channels[c], "channels[" + std::to_string(c) + "]"),
                                         lobeCount, count, tableCount, channelStats));
    if (channelStats) {
      anyStats = true;
      stats.push_back(std::move(*channelStats));
    } else {
      allStats = false;
    }
  }
  if (anyStats && !allStats) throw specError("channels", "either every channel has \"stats\" or none has");
  if (!model.wavelengthsNm.empty() && model.wavelengthsNm.size() != model.channels.size()) {
    throw specError("model.wavelengths_nm",
                    "must hold one wavelength per channel (" + std::to_string(model.channels.size()) + ")");
  }
  fit.channels = std::move(stats);
}

}  // namespace

std::string halfDifferenceTableDescription() {
  return "f(l, v) = exp(sum_kj a_kj hat_k(x) B_j(s)) [1/sr] per channel, x = sqrt(theta_h / 90 degrees) (K - 1), s = "
         "theta_d / 90 degrees, hat_k the hat of knot k, B_j the Bernstein polynomials of degree D, theta_h and "
         "theta_d Rusinkiewicz's half and difference angles; a_kj in channels[].half_difference at k (D + 1) + j";
}

std::string lobeModelDescription(LobeElevation elevation, ColorProfile colorProfile) {
  std::string text =
      "f(l, v) = k_d / pi + sum_k C_k (n_k + 2) / (2 pi) max(0, r_v . l)^n_k [1/sr], r_v = view mirrored about the "
      "normal, per channel";
  if (elevation == LobeElevation::Constant) {
    text += "; C_k, n_k constant";
  } else {
    text +=
        "; C_k, n_k varying with u = cos(theta_view): p(u) = p0^((1-t)^2) p1^(2t(1-t)) p2^(t^2), "
        "t = ln(u / min_cos) / ln(max_cos / min_cos) clamped to [0, 1]";
  }
  if (colorProfile == ColorProfile::None) return text;
  return text +
         "; k_d, C_k and C_F each times their profile sum_j p_j binom(3, j) s^j (1 - s)^(3 - j), s = theta_d / 90 "
         "degrees, cos theta_d = l . h";
}

nlohmann::ordered_json fitFileToJson(const FitFile& file) {
  nlohmann::ordered_json document;
  document["format"] = kFitFileFormat;
  document["version"] = kFitFileVersion;
  document["generator"] = std::string("brdfbake ") + BRDFBAKE_VERSION_STRING;
  if (file.hasSource) document["source"] = sourceToJson(file.source);
  document["model"] = modelToJson(file.fit.model);
  if (file.hasFitInfo) document["fit"] = fitSectionToJson(file.fit);
  nlohmann::ordered_json channels = nlohmann::ordered_json::array();
  for (std::size_t c = 0; c < file.fit.model.channels.size(); ++c) {
    channels.push_back(
        channelToJson(file.fit.model.channels[c], c < file.fit.channels.size() ? &file.fit.channels[c] : nullptr));
  }
  document["channels"] = channels;
  return document;
}

bool isFitFileJson(const nlohmann::json& document) {
  return document.is_object() && document.contains("format") && document["format"] == kFitFileFormat;
}

FitFile fitFileFromJson(const nlohmann::json& document, const std::string& label) {
  try {
    JsonObjectReader root(document, "");
    FitFile file;
    readFormatAndVersion(root);
    file.hasSource = root.has("source");
    if (file.hasSource) readSource(root.object("source"), file.source);
    const int lobeCount = readModelShape(root.object("model"), file.fit.model);
    if (root.has("fit")) {
      readFitSection(root.object("fit"), file.fit);
    } else {
      file.hasFitInfo = false;
    }
    readChannels(root, lobeCount, file.fit);
    root.finish();
    try {
      file.fit.model.validate();
    } catch (const Error& e) {
      throw specError("channels", e.what());
    }
    return file;
  } catch (const Error& e) {
    throw Error(e.kind() == Error::Kind::InvalidArgument ? Error::Kind::InvalidInput : e.kind(),
                printable(label) + ": " + e.what());
  }
}

FitFile readFitFile(const fs::path& path) { return fitFileFromJson(readJsonFile(path), path.string()); }

void writeFitFile(const fs::path& path, const FitFile& file) {
  writeFileAtomically(path, fitFileToJson(file).dump(2) + "\n");
}

}  // namespace brdfbake
