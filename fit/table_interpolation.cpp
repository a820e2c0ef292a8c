#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/table_interpolation.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {
namespace {

constexpr double kAngleTolerance = 1e-5;

Vec3 unit(const Vec3& v, const char* what) {
  const double norm = v.norm();
  require(v.allFinite() && norm > 0.0, std::string(what) + " must be a finite non-zero vector");
  return v / norm;
}

double angleBetween(const Vec3& a, const Vec3& b) {
  // atan2 form: accurate for small angles, where acos(dot) loses half the digits.
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

TableInterpolator::TableInterpolator(MeasuredTable table, int neighbours)
    : table_(std::move(table)), neighbours_(neighbours) {
  require(neighbours >= 1, "table interpolation: neighbours must be >= 1");
  table_.validate();
  const std::string label = table_.label();
  if (table_.size() == 0) throw Error(Error::Kind::InvalidInput, label + ": no samples to interpolate");
  for (std::size_t i = 0; i < table_.size(); ++i) {
    const auto& a = table_.angles[i];
    auto group = std::find_if(groups_.begin(), groups_.end(), [&](const Group& g) {
      return std::abs(g.thetaIn - a.thetaIn) < kAngleTolerance && std::abs(g.phiIn - a.phiIn) < kAngleTolerance;
    });
    if (group == groups_.end()) {
      groups_.push_back({a.thetaIn, a.phiIn, {}, {}});
      group = groups_.end() - 1;
    }
    group->samples.push_back(i);
    group->outgoing.push_back(table_.outgoingDirection(i));
  }
}

Eigen::VectorXd TableInterpolator::evaluate(const Vec3& wiRaw, const Vec3& woRaw) const {
  const Vec3 wi = unit(wiRaw, "wi"), wo = unit(woRaw, "wo");
  const auto channels = static_cast<Eigen::Index>(table_.channelCount());
  if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return Eigen::VectorXd::Zero(channels);
  const double thetaIn = std::acos(std::clamp(wi.z(), -1.0, 1.0));
  const double phiIn = std::hypot(wi.x(), wi.y()) > 1e-12 ? std::atan2(wi.y(), wi.x()) : 0.0;

  // The group of the nearest incident angle (first of equals).
  const Group* best = &groups_.front();
  for (const auto& g : groups_) {
    if (std::abs(g.thetaIn - thetaIn) < std::abs(best->thetaIn - thetaIn) - 1e-12) best = &g;
  }
  // Rotate the view about the normal so that the query's incident azimuth becomes the group's,
  // and mirror it about the group's plane of incidence.
  const double rotation = best->phiIn - phiIn;
  const Vec3 view = Eigen::AngleAxisd(rotation, Vec3::UnitZ()) * wo;
  const Vec3 axis(std::cos(best->phiIn), std::sin(best->phiIn), 0.0);  // in the plane of incidence
  const Vec3 planeNormal = Vec3::UnitZ().cross(axis);
  const Vec3 mirrored = view - 2.0 * view.dot(planeNormal) * planeNormal;

  std::vector<std::pair<double, std::size_t>> nearest;
  nearest.reserve(best->samples.size());
  for (std::size_t j = 0; j < best->samples.size(); ++j) {
    const double d = std::min(angleBetween(view, best->outgoing[j]), angleBetween(mirrored, best->outgoing[j]));
    nearest.emplace_back(d, best->samples[j]);
  }
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(neighbours_), nearest.size());
  std::partial_sort(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(k), nearest.end());
  if (nearest.front().first < 1e-9)
    return table_.values.row(static_cast<Eigen::Index>(nearest.front().second)).transpose();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(channels);
  double weights = 0.0;
  for (std::size_t j = 0; j < k; ++j) {
    const double w = 1.0 / (nearest[j].first * nearest[j].first);
    sum += w * table_.values.row(static_cast<Eigen::Index>(nearest[j].second)).transpose();
    weights += w;
  }
  return sum / weights;
}

}  // namespace brdfbake
