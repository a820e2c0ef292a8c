// The baker's tabulated paths for Cook-Torrance against the general path (the model evaluated at
// every sample, no tables) and against the model written out by hand: texel by texel and under
// the value-weighted error measure of docs/accuracy.md.
#include <gtest/gtest.h>
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include "map_function_support.hpp"

namespace brdfbake {
namespace {

using test::GeneralOnly;

double maxDifference(const Image& a, const Image& b) {
  double worst = 0.0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) worst = std::max(worst, (a.at(x, y) - b.at(x, y)).abs().maxCoeff());
  return worst;
}

double peakOf(const Image& image) {
  double peak = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) peak = std::max(peak, image.at(x, y).head<3>().maxCoeff());
  return peak;
}

std::shared_ptr<CookTorranceMaterial> cookTorrance(CookTorranceMode mode, MicrofacetDistribution distribution,
                                                   double roughness, double specularWeight = 1.0,
                                                   const Rgb& diffuse = Rgb::Zero()) {
  CookTorranceParams params;
  params.mode = mode;
  params.distribution = distribution;
  params.roughness = roughness;
  params.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  params.specularWeight = specularWeight;
  params.diffuse = diffuse;
  return std::make_shared<CookTorranceMaterial>(params);
}

// Texel-wise within `tolerance` of the peak, and the same error bound (docs/accuracy.md) to 1 % of itself.
void expectMatchesGeneralPath(const Parameterization& map, const MapFunction& function, const std::string& path,
                              const std::string& what, double tolerance = 1e-5) {
  BakeOptions options;
  options.samplesPerTexel = 4;
  const auto [fast, summary] = bakeMap(map, function, options);
  const auto [slow, general] = bakeMap(map, GeneralOnly(function), options);
  EXPECT_EQ(summary.path, path) << what;
  EXPECT_EQ(general.path, "general") << what;
  const double peak = peakOf(slow);
  ASSERT_GT(peak, 0.0) << what;
  EXPECT_LT(maxDifference(fast, slow), tolerance * peak) << what;
  ErrorOptions errorOptions;
  errorOptions.samples = 4000;
  errorOptions.highlightGrid = 64;
  const bool visible = map.kind() == ParameterizationKind::Sphere;
  const ErrorProbes probes(function, errorOptions);
  const double fastBound = measureMapError(fast, map, probes, visible).bound(visible);
  const double slowBound = measureMapError(slow, map, probes, visible).bound(visible);
  EXPECT_NEAR(fastBound, slowBound, 0.01 * slowBound + 1e-9) << what;
}

TEST(FastPaths, CookTorranceReflectanceTakesTheRadialPaths) {
  for (const auto distribution : {MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}) {
    const MaterialMapFunction function(cookTorrance(CookTorranceMode::Reflectance, distribution, 0.3), {},
                                       Vec3::UnitZ());
    expectMatchesGeneralPath(*makeParameterization(ParameterizationKind::Sphere, 64), function, "radial-view-axis",
                             "reflectance, sphere");
    expectMatchesGeneralPath(*makeParameterization(ParameterizationKind::Paraboloid, 48), function, "radial",
                             "reflectance, paraboloid");
  }
}

TEST(FastPaths, CookTorranceLightingTakesTheMicrofacetPath) {
  const std::vector<DirectionalLight> lights{{Vec3(1, 1, 1).normalized(), Rgb::Ones()},
                                             {Vec3(-0.3, 0.2, -1).normalized(), Rgb(0.5, 0.2, 1.0)},
                                             {Vec3(0, 0.1, 1).normalized(), Rgb(1.0, 0.9, 0.8)}};
  for (const auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                          ParameterizationKind::LatLong}) {
    for (const auto distribution : {MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}) {
      for (const double roughness : {0.05, 0.3, 1.0}) {
        const auto material =
            cookTorrance(CookTorranceMode::Lighting, distribution, roughness, 0.7, Rgb(0.2, 0.5, 0.1));
        const MaterialMapFunction function(material, lights, Vec3::UnitZ());
        // Within 1.4e-7 of the peak on every map (the sphere map's normals computed directly).
        expectMatchesGeneralPath(*makeParameterization(kind, 48), function, "microfacet",
                                 std::string(toString(kind)) + " m " + std::to_string(roughness), 1e-6);
      }
    }
  }
}

TEST(FastPaths, CookTorranceLightingMatchesTheFormulaAtTexelCentres) {
  // One sample per texel: the texel holds the model at its centre's direction. Beckmann D and
  // Cook-Torrance G written out here (Cook & Torrance 1981; Zimmons & Bastos 1999 Eq. 7).
  const double m = 0.3;
  const auto material = cookTorrance(CookTorranceMode::Lighting, MicrofacetDistribution::Beckmann, m);
  const Vec3 l = Vec3(1, 1, 1).normalized(), v = Vec3::UnitZ();
  const MaterialMapFunction function(material, {{l, Rgb::Ones()}}, v);
  const SphereMap map(64);
  BakeOptions options;
  options.samplesPerTexel = 1;
  const auto [image, summary] = bakeMap(map, function, options);
  ASSERT_EQ(summary.path, "microfacet");
  double worst = 0.0, peak = 0.0;
  for (int y = 2; y < 62; y += 3) {
    for (int x = 2; x < 62; x += 3) {
      const auto r = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      if (!r || map.texelCoverage(x, y) < 1.0) continue;
      const Vec3 n = (*r + v).normalized(), h = (l + v).normalized();
      const double nh = n.dot(h), nv = n.dot(v), nl = n.dot(l), vh = v.dot(h);
      double expected = 0.0;
      if (nl > 0.0 && nh > 0.0) {
        const double tan2 = (1.0 - nh * nh) / (nh * nh);
        const double d = std::exp(-tan2 / (m * m)) / (kPi * m * m * std::pow(nh, 4));
        const double g = std::min({1.0, 2.0 * nh * nv / vh, 2.0 * nh * nl / vh});
        expected = d * g / (4.0 * nl * nv) * nl;
      }
      const Rgb f = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538))(vh);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(image.at(x, y)[c] - expected * f[c]));
        peak = std::max(peak, expected * f[c]);
      }
    }
  }
  ASSERT_GT(peak, 0.5);
  EXPECT_LT(worst, 1e-5 * peak);
}

}  // namespace
}  // namespace brdfbake
