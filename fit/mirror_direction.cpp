#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/mirror_profile.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {

void MirrorProfile::validate() const {
  require(!thetas.empty(), "mirror profile: no angles");
  require(values.rows() == static_cast<Eigen::Index>(thetas.size()) && values.cols() > 0,
          "mirror profile: one row of values per angle");
  require(offsets.rows() == values.rows() && offsets.cols() == values.cols(), "mirror profile: offsets do not match values");
  require(channelNames.size() == channelCount(), "mirror profile: one name per channel");
  for (std::size_t i = 0; i < thetas.size(); ++i) {
    require(std::isfinite(thetas[i]) && (i == 0 || thetas[i] > thetas[i - 1]), "mirror profile: angles must increase");
  }
  require(values.allFinite() && offsets.allFinite(), "mirror profile: values must be finite");
}

Eigen::VectorXd MirrorProfile::at(double theta) const {
  if (!(theta > thetas.front())) return values.row(0).transpose();
  if (theta >= thetas.back()) return values.row(values.rows() - 1).transpose();
  const auto upper = std::upper_bound(thetas.begin(), thetas.end(), theta);
  const auto i = static_cast<Eigen::Index>(upper - thetas.begin());
  const double a = thetas[static_cast<std::size_t>(i - 1)], b = thetas[static_cast<std::size_t>(i)];
  const double s = (theta - a) / (b - a);
  return ((1.0 - s) * values.row(i - 1) + s * values.row(i)).transpose();
}

MirrorProfile strongestNearMirrorProfile(const MeasuredTable& table, double windowRadians) {
  require(std::isfinite(windowRadians) && windowRadians > 0.0 && windowRadians <= kPi + 1e-12,
          "mirror profile: window must be in (0, 180] degrees");
  table.validate();
  const std::string label = table.sourceFile.empty() ? std::string("table") : table.sourceFile;
  if (table.size() == 0) throw Error(Error::Kind::InvalidInput, label + ": no samples for a mirror profile");
  MirrorProfile profile;
  profile.thetas = table.incidentThetas();
  profile.channelNames = table.channelNames;
  if (table.kind == ChannelKind::Spectral) profile.wavelengthsNm = table.wavelengthsNm;
  const auto rows = static_cast<Eigen::Index>(profile.thetas.size());
  const auto channels = static_cast<Eigen::Index>(table.channelCount());
  profile.values.resize(rows, channels);
  profile.offsets.resize(rows, channels);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const auto samples = table.samplesAtIncidentTheta(profile.thetas[static_cast<std::size_t>(r)]);
    std::vector<double> offsets;
    std::size_t nearest = samples.front();
    double nearestOffset = HUGE_VAL;
    for (std::size_t i : samples) {
      const Vec3 mirror = reflect(table.incidentDirection(i), Vec3(Vec3::UnitZ()));
      const Vec3 out = table.outgoingDirection(i);
      const double offset = std::atan2(mirror.cross(out).norm(), mirror.dot(out));
      offsets.push_back(offset);
      if (offset < nearestOffset) nearestOffset = offset, nearest = i;
    }
    for (Eigen::Index c = 0; c < channels; ++c) {
      double best = -HUGE_VAL, bestOffset = 0.0;
      for (std::size_t j = 0; j < samples.size(); ++j) {
        if (offsets[j] > windowRadians) continue;
        const double v = table.values(static_cast<Eigen::Index>(samples[j]), c);
        if (v > best) best = v, bestOffset = offsets[j];
      }
      if (best == -HUGE_VAL) best = table.values(static_cast<Eigen::Index>(nearest), c), bestOffset = nearestOffset;
      profile.values(r, c) = best;
      profile.offsets(r, c) = bestOffset;
    }
  }
  profile.validate();
  return profile;
}

MirrorProfile fittedMirrorProfile(const LobeModel& model, const std::vector<double>& thetas) {
  model.validate();
  MirrorProfile profile;
  profile.thetas = thetas;
  for (const auto& channel : model.channels) profile.channelNames.push_back(channel.name);
  profile.wavelengthsNm = model.wavelengthsNm;
  const auto channels = static_cast<Eigen::Index>(model.channelCount());
  profile.values.resize(static_cast<Eigen::Index>(thetas.size()), channels);
  profile.offsets = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(thetas.size()), channels);
  for (std::size_t r = 0; r < thetas.size(); ++r) {
    for (Eigen::Index c = 0; c < channels; ++c) {
      profile.values(static_cast<Eigen::Index>(r), c) = model.mirrorValue(static_cast<std::size_t>(c), std::cos(thetas[r]));
    }
  }
  profile.validate();
  return profile;
}

MirrorProfileMaterial::MirrorProfileMaterial(MirrorProfile profile, std::string modelName)
    : profile_(std::move(profile)), modelName_(std::move(modelName)) {
  profile_.validate();
  require(profile_.channelCount() == 3, "mirror profile material: needs R, G, B channels (convert the table with toRgb)");
}

Rgb MirrorProfileMaterial::unlit(const ShadingGeometry& g) const {
  const double theta = std::acos(clampFinite(g.normal.dot(g.view), -1.0, 1.0));
  return profile_.at(theta).array();
}

}  // namespace brdfbake
