#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/mirror_direction.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {

void MirrorDirectionTable::validate() const {
  require(!thetas.empty(), "mirror-direction table: no angles");
  require(values.rows() == static_cast<Eigen::Index>(thetas.size()) && values.cols() > 0,
          "mirror-direction table: one row of values per angle");
  require(offsets.rows() == values.rows() && offsets.cols() == values.cols(),
          "mirror-direction table: offsets do not match values");
  require(channelNames.size() == channelCount(), "mirror-direction table: one name per channel");
  for (std::size_t i = 0; i < thetas.size(); ++i) {
    require(std::isfinite(thetas[i]) && (i == 0 || thetas[i] > thetas[i - 1]),
            "mirror-direction table: angles must increase");
  }
  require(values.allFinite() && offsets.allFinite(), "mirror-direction table: values must be finite");
}

Eigen::VectorXd MirrorDirectionTable::at(double theta) const {
  if (!(theta > thetas.front())) return values.row(0).transpose();
  if (theta >= thetas.back()) return values.row(values.rows() - 1).transpose();
  const auto upper = std::upper_bound(thetas.begin(), thetas.end(), theta);
  const auto i = static_cast<Eigen::Index>(upper - thetas.begin());
  const double a = thetas[static_cast<std::size_t>(i - 1)], b = thetas[static_cast<std::size_t>(i)];
  const double s = (theta - a) / (b - a);
  return ((1.0 - s) * values.row(i - 1) + s * values.row(i)).transpose();
}

MirrorDirectionTable strongestNearMirrorTable(const MeasuredTable& table, double windowRadians) {
  require(std::isfinite(windowRadians) && windowRadians > 0.0 && windowRadians <= kPi + 1e-12,
          "mirror-direction table: window must be in (0, 180] degrees");
  table.validate();
  const std::string label = table.label();
  if (table.size() == 0) throw Error(Error::Kind::InvalidInput, label + ": no samples for a mirror-direction table");
  MirrorDirectionTable result;
  result.thetas = table.incidentThetas();
  result.channelNames = table.channelNames;
  if (table.kind == ChannelKind::Spectral) result.wavelengthsNm = table.wavelengthsNm;
  const auto rows = static_cast<Eigen::Index>(result.thetas.size());
  const auto channels = static_cast<Eigen::Index>(table.channelCount());
  result.values.resize(rows, channels);
  result.offsets.resize(rows, channels);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const auto samples = table.samplesAtIncidentTheta(result.thetas[static_cast<std::size_t>(r)]);
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
      result.values(r, c) = best;
      result.offsets(r, c) = bestOffset;
    }
  }
  result.validate();
  return result;
}

MirrorDirectionTable fittedMirrorTable(const LobeModel& model, const std::vector<double>& thetas) {
  model.validate();
  MirrorDirectionTable result;
  result.thetas = thetas;
  for (const auto& channel : model.channels) result.channelNames.push_back(channel.name);
  result.wavelengthsNm = model.wavelengthsNm;
  const auto channels = static_cast<Eigen::Index>(model.channelCount());
  result.values.resize(static_cast<Eigen::Index>(thetas.size()), channels);
  result.offsets = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(thetas.size()), channels);
  for (std::size_t r = 0; r < thetas.size(); ++r) {
    for (Eigen::Index c = 0; c < channels; ++c) {
      result.values(static_cast<Eigen::Index>(r), c) =
          model.mirrorValue(static_cast<std::size_t>(c), std::cos(thetas[r]));
    }
  }
  result.validate();
  return result;
}

MirrorDirectionMaterial::MirrorDirectionMaterial(MirrorDirectionTable table, std::string modelName)
    : table_(std::move(table)), modelName_(std::move(modelName)) {
  table_.validate();
  require(table_.channelCount() == 3,
          "mirror-direction material: needs R, G, B channels (convert the table with toRgb)");
}

Rgb MirrorDirectionMaterial::unlit(const ShadingGeometry& g) const {
  const double theta = std::acos(clampFinite(g.normal.dot(g.view), -1.0, 1.0));
  return table_.at(theta).array();
}

}  // namespace brdfbake
