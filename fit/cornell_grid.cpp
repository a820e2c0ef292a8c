#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include <cmath>
#include <random>
#include <sstream>

namespace brdfbake {
namespace {

double round6(double x) { return std::round(x * 1e6) / 1e6; }

constexpr double kHoleRadiusDegrees = 17.0;

}  // namespace

bool isCornellHole(const SampleAngles& a) {
  const double cosAngle = directionFromAngles(a.thetaIn, a.phiIn).dot(directionFromAngles(a.thetaOut, a.phiOut));
  if (cosAngle > std::cos(radians(kHoleRadiusDegrees))) return true;
  // The one further missing sample of every file: theta_i 80, outer ring, phi_s -175 degrees.
  return std::abs(a.thetaIn - radians(80.0)) < 1e-4 &&
         std::abs(a.thetaOut - 2.0 * std::asin(0.9 / std::sqrt(2.0))) < 1e-4 &&
         std::abs(a.phiOut - radians(-175.0)) < 1e-4;
}

std::vector<SampleAngles> cornellSampleAngles(bool holes) {
  std::vector<SampleAngles> angles;
  for (int i = 1; i <= 8; ++i) {
    const double thetaIn = round6(radians(10.0 * i));
    for (int k = 0; k <= 9; ++k) {
      const double thetaOut = round6(2.0 * std::asin(k / (10.0 * std::sqrt(2.0))));
      const int azimuths = k == 0 ? 1 : 4 * k + 1;
      for (int j = 0; j < azimuths; ++j) {
        // j = 0 is the mirror side, stored as +180 degrees; ring 0 is the normal at phi 0.
        const double phiDegrees = k == 0 ? 0.0 : (j == 0 ? 180.0 : -180.0 + j * 45.0 / k);
        const SampleAngles a{thetaIn, 0.0, thetaOut, round6(radians(phiDegrees))};
        if (holes && isCornellHole(a)) continue;
        angles.push_back(a);
      }
    }
  }
  return angles;
}

MeasuredTable makeSyntheticTable(const LobeModel& model, double noise, std::uint32_t seed, bool holes) {
  model.validate();
  require(std::isfinite(noise) && noise >= 0.0 && noise < 1.0, "synthetic table: noise must be in [0, 1)");
  MeasuredTable table;
  table.angles = cornellSampleAngles(holes);
  const auto channels = static_cast<Eigen::Index>(model.channelCount());
  table.values.resize(static_cast<Eigen::Index>(table.angles.size()), channels);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss;
  for (std::size_t i = 0; i < table.angles.size(); ++i) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    for (Eigen::Index c = 0; c < channels; ++c) {
      const double g = gauss(rng);
      table.values(static_cast<Eigen::Index>(i), c) =
          model.evaluate(static_cast<std::size_t>(c), wi, wo) * (1.0 + noise * g);
    }
  }
  for (const auto& channel : model.channels) table.channelNames.push_back(channel.name);
  if (!model.wavelengthsNm.empty()) {
    table.kind = ChannelKind::Spectral;
    table.wavelengthsNm = model.wavelengthsNm;
  } else {
    table.kind = model.channelCount() == 1 ? ChannelKind::Monochrome : ChannelKind::Trichromatic;
  }
  std::ostringstream comment;
  comment << "synthetic table from known lobes (" << toString(model.elevation) << ", " << noise * 100.0
          << " % relative Gaussian noise, seed " << seed << (holes ? ", Cornell holes" : ", no holes") << ")";
  table.header = {{"SAMPLE_NAME", "synthetic lobes"},
                  {"LAB_COMMENTS", comment.str()},
                  {"SYSTEM_NAME", "brdfbake makeSyntheticTable on the Cornell gonioreflectometer geometry"},
                  {"MEAS_NAME", "BRDF"}};
  table.format = TableFormat::Astm;
  table.validate();
  return table;
}

MeasuredTable sampleMerlOnCornellGrid(const MerlTable& merl) {
  MeasuredTable table;
  table.kind = ChannelKind::Trichromatic;
  table.channelNames = {"R", "G", "B"};
  table.format = TableFormat::Merl;
  table.sourceFile = merl.sourceFile();
  std::vector<Rgb> values;
  std::size_t unmeasured = 0;
  for (const auto& a : cornellSampleAngles(false)) {
    const auto value =
        merl.evaluate(directionFromAngles(a.thetaIn, a.phiIn), directionFromAngles(a.thetaOut, a.phiOut));
    if (!value) {
      ++unmeasured;
      continue;
    }
    table.angles.push_back(a);
    values.push_back(*value);
  }
  table.values.resize(static_cast<Eigen::Index>(values.size()), 3);
  for (std::size_t i = 0; i < values.size(); ++i)
    table.values.row(static_cast<Eigen::Index>(i)) = values[i].transpose();
  table.notes.push_back(
      "MERL table sampled on the Cornell grid (8 incident angles x 190 directions, nearest MERL bin): " +
      std::to_string(values.size()) + " samples" +
      (unmeasured ? ", " + std::to_string(unmeasured) + " directions skipped (unmeasured bins)" : ""));
  table.validate();
  return table;
}

MeasuredTable readTableForFitting(const std::filesystem::path& path, TableFormat format) {
  if (format == TableFormat::Auto) format = detectTableFormat(path);
  if (format == TableFormat::Merl) return sampleMerlOnCornellGrid(readMerl(path));
  return readMeasuredTable(path, format);
}

}  // namespace brdfbake
