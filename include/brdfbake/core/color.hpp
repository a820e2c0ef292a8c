#pragma once
/// @file
/// Linear RGB(A) values as stored in maps. Colours are linear (scene-referred) unless a function
/// says otherwise; only 8-bit output applies the sRGB transfer curve.

#include <Eigen/Core>
#include <array>

namespace brdfbake {

using Rgb = Eigen::Array3d;
using Rgba = Eigen::Array4d;

/// True when every component is finite.
template <class Derived>
bool allFinite(const Eigen::ArrayBase<Derived>& a) {
  return a.isFinite().all();
}

}  // namespace brdfbake
