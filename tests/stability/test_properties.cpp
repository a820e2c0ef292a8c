// Property tests over random directions and parameters: no NaN or Inf, round trips hold,
// normalised lobes never reflect more than they receive.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

namespace brdfbake {
namespace {

// A random unit vector (any direction, including exact axes and near-degenerate ones).
rc::Gen<Vec3> genDirection() {
  return rc::gen::map(rc::gen::tuple(rc::gen::inRange(-1000000, 1000001), rc::gen::inRange(-1000000, 1000001),
                                     rc::gen::inRange(-1000000, 1000001), rc::gen::element(1.0, 1e-6, 1e-13)),
                      [](const std::tuple<int, int, int, double>& t) {
                        Vec3 v(std::get<0>(t), std::get<1>(t), std::get<2>(t));
                        if (v.squaredNorm() == 0) v = Vec3::UnitZ();
                        // Sometimes squash towards an axis, to reach the singular neighbourhoods.
                        const double squash = std::get<3>(t);
                        v.x() *= squash, v.y() *= squash;
                        return Vec3(v.normalized());
                      });
}

RC_GTEST_PROP(Properties, ForwardIsAlwaysFinite, ()) {
  const Vec3 d = *genDirection();
  const int kind = *rc::gen::inRange(0, 4);
  const auto map = makeParameterization(static_cast<ParameterizationKind>(kind), *rc::gen::inRange(1, 300));
  const MapAddress a = map->getAddressFor(d);
  RC_ASSERT(a.pixel.allFinite());
  RC_ASSERT(a.pixel.x() >= 0.0 && a.pixel.x() <= map->width());
  RC_ASSERT(a.pixel.y() >= 0.0 && a.pixel.y() <= map->height());
}

RC_GTEST_PROP(Properties, RoundTripsHoldAwayFromSingularSets, ()) {
  const Vec3 d = *genDirection();
  const int kind = *rc::gen::inRange(0, 4);
  const auto map = makeParameterization(static_cast<ParameterizationKind>(kind), 256);
  // Singular sets: sphere map rim (-z), lat-long poles.
  RC_PRE(!(kind == 0 && d.z() < -0.999));
  RC_PRE(!(kind == 3 && std::abs(d.y()) > 0.999999));
  const auto back = map->getDirectionFor(map->getAddressFor(d).pixel);
  RC_ASSERT(back.has_value());
  RC_ASSERT((*back - d).norm() < 1e-9);
}

RC_GTEST_PROP(Properties, ShadingIsAlwaysFinite, ()) {
  const Vec3 r = *genDirection(), l = *genDirection();
  const double n = *rc::gen::element(0.0, 1e-6, 0.5, 1.0, 50.0, 1e3, 1e6);
  const ShadingGeometry g = geometryForReflection(r, Vec3::UnitZ());
  const PhongMaterial phong(Rgb::Ones(), n, Rgb::Constant(0.5));
  RC_ASSERT(allFinite(phong.shade(g, l)));
  for (auto policy : {BlinnConversion::Exact, BlinnConversion::FourN}) {
    const BlinnPhongMaterial blinn(Rgb::Ones(), std::max(n, 1e-6), policy, Rgb::Constant(0.5));
    RC_ASSERT(allFinite(blinn.shade(g, l)));
  }
}

// Directional albedo of the normalised Phong lobe (n + 2)/(2 pi) max(0, r.l)^n for a view at
// angle thetaView: ∫ f(l) max(0, n.l) dω_l over the upper hemisphere, by quadrature in polar
// coordinates about the lobe axis r (which resolves the lobe).
double normalizedPhongAlbedo(double n, double thetaView) {
  const Vec3 normal = Vec3::UnitZ();
  const Vec3 view(std::sin(thetaView), 0, std::cos(thetaView));
  const Vec3 r = reflect(view, normal);
  const Vec3 t1 = anyPerpendicular(r), t2 = r.cross(t1);
  const int steps = 400, turns = 200;
  const double width = std::min(kPi / 2, 8.0 / std::sqrt(n + 1.0));  // the lobe is negligible beyond
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double alpha = (i + 0.5) * width / steps;
    const double lobe = phongNormalization(n) * std::pow(std::cos(alpha), n) * std::sin(alpha);
    for (int j = 0; j < turns; ++j) {
      const double phi = (j + 0.5) * kTwoPi / turns;
      const Vec3 l = std::cos(alpha) * r + std::sin(alpha) * (std::cos(phi) * t1 + std::sin(phi) * t2);
      sum += lobe * std::max(0.0, l.dot(normal));
    }
  }
  return sum * (width / steps) * (kTwoPi / turns);
}

RC_GTEST_PROP(Properties, NormalisedPhongNeverReflectsMoreThanItReceives, ()) {
  const double n = *rc::gen::inRange(0, 300);
  const double theta = *rc::gen::inRange(0, 89) * kPi / 180.0;
  RC_ASSERT(normalizedPhongAlbedo(n, theta) <= 1.0 + 2e-3);
}

TEST(Properties, NormalisedPhongAlbedoIsOneAtNormalIncidence) {
  // Where the bound is tight: a check that the quadrature above is accurate.
  for (double n : {0.0, 1.0, 10.0, 100.0}) EXPECT_NEAR(normalizedPhongAlbedo(n, 0.0), 1.0, 2e-3) << n;
}

}  // namespace
}  // namespace brdfbake
