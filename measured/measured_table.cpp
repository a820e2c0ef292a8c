#include <brdfbake/core/named_values.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/core/error.hpp>

#include "measured_common.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace brdfbake {

namespace {
constexpr std::array<std::pair<TableFormat, std::string_view>, 5> kFormatNames{{
    {TableFormat::Auto, "auto"},
    {TableFormat::Astm, "astm"},
    {TableFormat::Pbrt, "pbrt"},
    {TableFormat::Merl, "merl"},
    {TableFormat::Mat, "mat"},
}};

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// Sorted distinct values, merging those within `tolerance` of the first of their group.
std::vector<double> distinctSorted(std::vector<double> values, double tolerance) {
  std::sort(values.begin(), values.end());
  std::vector<double> distinct;
  for (double v : values)
    if (distinct.empty() || v - distinct.back() > tolerance) distinct.push_back(v);
  return distinct;
}
}  // namespace

std::string_view toString(TableFormat format) {
  for (const auto& [f, name] : kFormatNames)
    if (f == format) return name;
  return "unknown";
}

TableFormat parseTableFormat(std::string_view name) {
  std::string lower(name);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return parseByName(
      lower, std::array{TableFormat::Auto, TableFormat::Astm, TableFormat::Pbrt, TableFormat::Merl, TableFormat::Mat},
      "table format (any case)");
}

Vec3 directionFromAngles(double theta, double phi) {
  const double s = std::sin(theta);
  return Vec3(s * std::cos(phi), s * std::sin(phi), std::cos(theta));
}

Vec3 MeasuredTable::incidentDirection(std::size_t i) const {
  const SampleAngles& a = angles.at(i);
  return directionFromAngles(a.thetaIn, a.phiIn);
}

Vec3 MeasuredTable::outgoingDirection(std::size_t i) const {
  const SampleAngles& a = angles.at(i);
  return directionFromAngles(a.thetaOut, a.phiOut);
}

std::vector<double> MeasuredTable::incidentThetas(double tolerance) const {
  std::vector<double> thetas;
  thetas.reserve(angles.size());
  for (const SampleAngles& a : angles) thetas.push_back(a.thetaIn);
  return distinctSorted(std::move(thetas), tolerance);
}

std::vector<std::pair<double, double>> MeasuredTable::incidentAngles(double tolerance) const {
  std::vector<std::pair<double, double>> result;
  for (double theta : incidentThetas(tolerance)) {
    std::vector<double> phis;
    for (const SampleAngles& a : angles)
      if (std::abs(a.thetaIn - theta) <= tolerance) phis.push_back(a.phiIn);
    for (double phi : distinctSorted(std::move(phis), tolerance)) result.emplace_back(theta, phi);
  }
  return result;
}

std::vector<std::size_t> MeasuredTable::samplesAtIncidentTheta(double thetaIn, double tolerance) const {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < angles.size(); ++i)
    if (std::abs(angles[i].thetaIn - thetaIn) <= tolerance) indices.push_back(i);
  return indices;
}

std::string MeasuredTable::channelName(std::size_t c) const {
  return c < channelNames.size() ? channelNames[c] : std::to_string(c);
}

std::optional<std::size_t> MeasuredTable::channelIndex(std::string_view name) const {
  for (std::size_t c = 0; c < channelNames.size(); ++c)
    if (equalsIgnoringCase(channelNames[c], name)) return c;
  return std::nullopt;
}

std::string_view toString(RgbMethod method) { return method == RgbMethod::Cie1931 ? "cie1931" : "single_wavelengths"; }

RgbMethod parseRgbMethod(std::string_view name) {
  return parseByName(name, std::array{RgbMethod::Cie1931, RgbMethod::SingleWavelengths}, "rgb method");
}

MeasuredTable MeasuredTable::toRgb(RgbMethod method) const {
  validate();
  if (kind == ChannelKind::Trichromatic) return *this;

  MeasuredTable rgb;
  rgb.angles = angles;
  rgb.kind = ChannelKind::Trichromatic;
  rgb.channelNames = {"R", "G", "B"};
  rgb.sourceFile = sourceFile;
  rgb.format = format;
  rgb.header = header;
  rgb.notes = notes;
  rgb.values.resize(values.rows(), 3);

  if (kind == ChannelKind::Monochrome) {
    for (Eigen::Index c = 0; c < 3; ++c) rgb.values.col(c) = values.col(0);
    rgb.notes.push_back("RGB: the single channel '" + channelNames.front() + "' copied to R, G and B");
    return rgb;
  }

  if (method == RgbMethod::Cie1931) {
    const SpectrumToRgb converter(wavelengthsNm);
    rgb.values = values * converter.srgbWeights().transpose();
    rgb.notes.push_back(
        "RGB: linear sRGB from the spectrum through the CIE 1931 2-degree observer under D65 (a constant "
        "spectrum v gives (v, v, v)); the spectrum is held constant beyond " +
        measured::formatShortest(wavelengthsNm.front()) + "-" + measured::formatShortest(wavelengthsNm.back()) + " nm");
    const auto negatives = (rgb.values.array() < 0.0).count();
    if (negatives > 0)
      rgb.notes.push_back("RGB: " + std::to_string(negatives) + " of " + std::to_string(rgb.values.size()) +
                          " values are negative (colours outside the sRGB gamut, or negative input); kept");
    return rgb;
  }

  const WavelengthPick pick = nearestWavelengths(wavelengthsNm);
  for (Eigen::Index c = 0; c < 3; ++c) rgb.values.col(c) = values.col(static_cast<Eigen::Index>(pick.index[c]));
  std::string note = "RGB: single wavelengths (Zimmons & Bastos 1999 section 8):";
  static constexpr const char* kChannel[3] = {"R", "G", "B"};
  for (std::size_t c = 0; c < 3; ++c) {
    note += std::string(c ? "," : "") + " " + kChannel[c] + " = " + measured::formatShortest(pick.usedNm[c]) + " nm";
    if (pick.usedNm[c] != pick.requestedNm[c])
      note += " (nearest available to " + measured::formatShortest(pick.requestedNm[c]) + " nm)";
  }
  rgb.notes.push_back(note);
  return rgb;
}

MeasuredTable MeasuredTable::withMirroredHalf(double tolerance) const {
  validate();
  for (const SampleAngles& a : angles)
    require(std::abs(a.phiIn) <= tolerance,
            "withMirroredHalf: needs phi_i = 0 for every sample, found " + measured::formatShortest(a.phiIn));
  std::vector<std::size_t> toMirror;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    const double wrapped = std::remainder(angles[i].phiOut, kTwoPi);  // in [-pi, pi]
    const bool inPlane = std::abs(wrapped) <= tolerance || kPi - std::abs(wrapped) <= tolerance;
    if (angles[i].thetaOut > tolerance && !inPlane) toMirror.push_back(i);
  }
  MeasuredTable full = *this;
  full.angles.reserve(angles.size() + toMirror.size());
  full.values.conservativeResize(values.rows() + static_cast<Eigen::Index>(toMirror.size()), values.cols());
  Eigen::Index row = values.rows();
  for (std::size_t i : toMirror) {
    SampleAngles mirrored = angles[i];
    mirrored.phiOut = -mirrored.phiOut;
    full.angles.push_back(mirrored);
    full.values.row(row++) = values.row(static_cast<Eigen::Index>(i));
  }
  full.notes.push_back("mirrored half added (phi_s -> -phi_s): " + std::to_string(toMirror.size()) +
                       " samples appended after the " + std::to_string(angles.size()) + " measured ones");
  return full;
}

std::string MeasuredTable::label() const {
  if (sourceFile.empty()) return "(table)";
  return sourceFile;
}

void MeasuredTable::validate() const {
  const auto fail = [&](const std::string& message) { return measured::malformed(label(), 0, message); };
  if (static_cast<std::size_t>(values.rows()) != angles.size())
    throw fail(std::to_string(angles.size()) + " sample angles but " + std::to_string(values.rows()) + " value rows");
  if (values.cols() < 1) throw fail("no channels");
  if (channelNames.size() != channelCount())
    throw fail(std::to_string(channelNames.size()) + " channel names for " + std::to_string(channelCount()) +
               " channels");
  switch (kind) {
    case ChannelKind::Spectral:
      if (wavelengthsNm.size() != channelCount())
        throw fail(std::to_string(wavelengthsNm.size()) + " wavelengths for " + std::to_string(channelCount()) +
                   " channels");
      for (std::size_t c = 0; c < wavelengthsNm.size(); ++c)
        if (!std::isfinite(wavelengthsNm[c]) || (c > 0 && !(wavelengthsNm[c] > wavelengthsNm[c - 1])))
          throw fail("wavelengths must be finite and strictly increasing");
      break;
    case ChannelKind::Trichromatic:
      if (channelCount() != 3) throw fail("an RGB table needs 3 channels, has " + std::to_string(channelCount()));
      break;
    case ChannelKind::Monochrome:
      if (channelCount() != 1) throw fail("a monochrome table needs 1 channel, has " + std::to_string(channelCount()));
      break;
  }
  if (!values.allFinite()) throw fail("non-finite values");
  for (std::size_t i = 0; i < angles.size(); ++i)
    measured::checkAngles(angles[i], label(), 0, "sample " + std::to_string(i) + ": ");
}

}  // namespace brdfbake
