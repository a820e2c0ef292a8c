#include <brdfbake/measured/measured_table.hpp>

#include <brdfbake/core/error.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace brdfbake {

MerlTable::MerlTable(std::vector<double> stored, std::string sourceFile)
    : stored_(std::move(stored)), sourceFile_(std::move(sourceFile)) {
  require(stored_.size() == 3 * kBinsPerChannel, "MerlTable: expected " + std::to_string(3 * kBinsPerChannel) +
                                                     " numbers, got " + std::to_string(stored_.size()));
  require(std::all_of(stored_.begin(), stored_.end(), [](double v) { return std::isfinite(v); }),
          "MerlTable: non-finite stored numbers");
}

MerlTable::HalfDiff MerlTable::halfDiffCoordinates(const Vec3& wi, const Vec3& wo) {
  // As MERL's std_coords_to_half_diff_coords: the half vector's angles, then wi expressed in
  // the frame where the half vector is the pole (rotate by -phi_half about z, -theta_half about y).
  const Vec3 in = wi.normalized();
  const Vec3 half = (in + wo.normalized()).normalized();
  HalfDiff hd{};
  hd.thetaHalf = std::acos(std::clamp(half.z(), -1.0, 1.0));
  hd.phiHalf = std::atan2(half.y(), half.x());
  const Vec3 diff =
      Eigen::AngleAxisd(-hd.thetaHalf, Vec3::UnitY()) * (Eigen::AngleAxisd(-hd.phiHalf, Vec3::UnitZ()) * in);
  hd.thetaDiff = std::acos(std::clamp(diff.z(), -1.0, 1.0));
  hd.phiDiff = std::atan2(diff.y(), diff.x());
  return hd;
}

int MerlTable::thetaHalfIndex(double thetaHalf) {
  if (thetaHalf <= 0.0) return 0;
  const double index = std::sqrt(thetaHalf / (kPi / 2) * kThetaHalfBins * kThetaHalfBins);
  return std::clamp(static_cast<int>(index), 0, kThetaHalfBins - 1);
}

int MerlTable::thetaDiffIndex(double thetaDiff) {
  return std::clamp(static_cast<int>(thetaDiff / (kPi / 2) * kThetaDiffBins), 0, kThetaDiffBins - 1);
}

int MerlTable::phiDiffIndex(double phiDiff) {
  if (phiDiff < 0.0) phiDiff += kPi;  // reciprocity: phi_diff and phi_diff + pi are the same bin
  return std::clamp(static_cast<int>(phiDiff / kPi * kPhiDiffBins), 0, kPhiDiffBins - 1);
}

std::optional<Rgb> MerlTable::bin(int thetaHalf, int thetaDiff, int phiDiff) const {
  require(thetaHalf >= 0 && thetaHalf < kThetaHalfBins && thetaDiff >= 0 && thetaDiff < kThetaDiffBins &&
              phiDiff >= 0 && phiDiff < kPhiDiffBins,
          "MerlTable::bin: index outside the grid");
  const std::size_t index =
      std::size_t(phiDiff) +
      std::size_t(kPhiDiffBins) * (std::size_t(thetaDiff) + std::size_t(kThetaDiffBins) * thetaHalf);
  Rgb value;
  for (std::size_t c = 0; c < 3; ++c) {
    const double stored = stored_[c * kBinsPerChannel + index];
    if (stored < 0.0) return std::nullopt;
    value[static_cast<Eigen::Index>(c)] = stored * kChannelScale[c];
  }
  return value;
}

std::optional<Rgb> MerlTable::evaluate(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) return std::nullopt;
  const HalfDiff hd = halfDiffCoordinates(wi, wo);
  return bin(thetaHalfIndex(hd.thetaHalf), thetaDiffIndex(hd.thetaDiff), phiDiffIndex(hd.phiDiff));
}

std::size_t MerlTable::unmeasuredBinCount() const {
  std::size_t count = 0;
  for (std::size_t i = 0; i < kBinsPerChannel; ++i)
    if (stored_[i] < 0.0 || stored_[i + kBinsPerChannel] < 0.0 || stored_[i + 2 * kBinsPerChannel] < 0.0) ++count;
  return count;
}

}  // namespace brdfbake
