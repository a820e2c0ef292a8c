#include <brdfbake/brdf/material.hpp>

namespace brdfbake {

ShadingGeometry geometryForReflection(const Vec3& reflected, const Vec3& view) {
  const Vec3 sum = reflected + view;
  const double norm = sum.norm();
  const Vec3 normal = norm > 1e-12 ? Vec3(sum / norm) : anyPerpendicular(view);
  return {normal, view, reflected};
}

}  // namespace brdfbake
