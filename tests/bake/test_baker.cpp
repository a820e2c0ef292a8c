// The baking engine against the exact model, its radial fast paths against the general path,
// and its limits.
#include <gtest/gtest.h>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/radial_table.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include "map_function_support.hpp"

#include <random>

namespace brdfbake {
namespace {

using test::GeneralOnly;

MaterialMapFunction phong(double exponent, const Vec3& light, const Rgb& diffuse = Rgb::Zero()) {
  return MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), exponent, diffuse), {{light, Rgb::Ones()}},
                             Vec3::UnitZ());
}

double maxDifference(const Image& a, const Image& b) {
  double worst = 0.0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) worst = std::max(worst, (a.at(x, y) - b.at(x, y)).abs().maxCoeff());
  return worst;
}

TEST(Baker, PhongEyeSphereMapMatchesTheAnalyticLobe) {
  // Foundation acceptance: n = 50, light at the eye, 256^2, 16 samples: within 1 % of the peak
  // for every direction more than 10 degrees from -z.
  const SphereMap map(256);
  const auto function = phong(50, Vec3::UnitZ());
  const auto [image, summary] = bakeMap(map, function);
  EXPECT_EQ(summary.path, "radial-view-axis");
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 r = Vec3(g(rng), g(rng), g(rng)).normalized();
    if (std::acos(std::clamp(-r.z(), -1.0, 1.0)) < radians(10)) continue;
    const double expected = std::pow(std::max(0.0, r.z()), 50);
    worst = std::max(worst, std::abs(sampleBilinear(image, map, r)[0] - expected));
  }
  EXPECT_LT(worst, 0.01);
}

class PhongParaboloid : public ::testing::TestWithParam<Vec3> {};

TEST_P(PhongParaboloid, MatchesInBothHemispheres) {
  const ParaboloidMap map(256);
  const Vec3 light = GetParam().normalized();
  const Image image = bake(map, phong(50, light));
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  double worstFront = 0.0, worstBack = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 r = Vec3(g(rng), g(rng), g(rng)).normalized();
    const double error = std::abs(sampleBilinear(image, map, r)[0] - std::pow(std::max(0.0, r.dot(light)), 50));
    (r.z() >= 0 ? worstFront : worstBack) = std::max(r.z() >= 0 ? worstFront : worstBack, error);
  }
  EXPECT_LT(worstFront, 0.01);
  EXPECT_LT(worstBack, 0.01);
  // The peak is where it belongs, in whichever half holds the light.
  EXPECT_GT(sampleBilinear(image, map, light)[0], 0.99);
}

// (1,1,1) from the issue peaks in the front half; (1,-1,-1) in the back; (1,0,0.02) straddles the seam.
INSTANTIATE_TEST_SUITE_P(Lights, PhongParaboloid, ::testing::Values(Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(1, 0, 0.02)));

TEST(Baker, RadialPathsAgreeWithTheGeneralPath) {
  // Also checks the culling of texels outside a lobe's support: sharp lobes cull most texels.
  for (const auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                          ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 48);
    for (const auto& [light, exponent] :
         {std::pair{Vec3(0, 0, 1), 20.0}, std::pair{Vec3(0.3, -0.5, 0.8), 20.0}, std::pair{Vec3(0, 0, -1), 500.0},
          std::pair{Vec3(1, 0.02, 0), 2000.0}, std::pair{Vec3(0.1, 1, 0), 1.0}}) {
      const auto function = phong(exponent, light.normalized());
      BakeOptions options;
      options.samplesPerTexel = 4;
      const Image fast = bake(*map, function, options);
      const Image slow = bake(*map, GeneralOnly(function), options);
      EXPECT_LT(maxDifference(fast, slow), 1e-5)
          << toString(kind) << " light " << light.transpose() << " n " << exponent;
    }
  }
}

TEST(Baker, SphereMapCullingKeepsEveryLitTexel) {
  // The sphere map's radial path culls runs of texels by an angular bound (SphereRadialPath):
  // lobes about random axes (some at the rim's -z, where the map's pulled samples all reflect),
  // several per map, narrow and wide, against the general path, which culls nothing. The
  // difference is table interpolation and rounding only (about 4e-7 of the peak).
  const SphereMap map(40);
  std::vector<Vec3> axes = test::randomDirections(12, 7);
  axes.push_back(-Vec3::UnitZ());
  axes.push_back(Vec3(0.3, 0.0, -1.0).normalized());
  for (const double exponent : {3.0, 200.0, 1000.0}) {
    for (std::size_t i = 0; i + 1 < axes.size(); i += 2) {
      std::vector<DirectionalLight> lights{{axes[i], Rgb(1.0, 0.5, 0.25)}, {axes[i + 1], Rgb(0.2, 1.0, 0.6)}};
      const MaterialMapFunction function(std::make_shared<PhongMaterial>(Rgb::Ones(), exponent), lights, Vec3::UnitZ());
      for (const int samples : {2, 9}) {
        BakeOptions options;
        options.samplesPerTexel = samples;
        const auto [fast, summary] = bakeMap(map, function, options);
        ASSERT_EQ(summary.path, "radial");
        ASSERT_EQ(summary.deltaLobes, 0) << "a deposited lobe is not sampled by either path";
        const Image slow = bake(map, GeneralOnly(function), options);
        double peak = 0.0;
        for (int y = 0; y < slow.height(); ++y)
          for (int x = 0; x < slow.width(); ++x) peak = std::max(peak, double(slow.at(x, y).head<3>().maxCoeff()));
        EXPECT_LT(maxDifference(fast, slow), 2e-6 * peak) << "n " << exponent << " axes " << axes[i].transpose() << ", "
                                                          << axes[i + 1].transpose() << ", " << samples << " samples";
      }
    }
  }
}

TEST(Baker, DiffuseWithEyeLightUsesTheViewAxisTable) {
  const SphereMap map(64);
  const auto function = phong(10, Vec3::UnitZ(), Rgb(0.5, 0.25, 0.0));
  const auto [fast, summary] = bakeMap(map, function);
  EXPECT_EQ(summary.path, "radial-view-axis");
  EXPECT_LT(maxDifference(fast, bake(map, GeneralOnly(function))), 1e-5);
}

TEST(Baker, IsDeterministicAcrossThreadCounts) {
  const SphereMap map(64);
  const auto function = phong(30, Vec3(1, 0, 1).normalized());
  const Context one({.threads = 1}), two({.threads = 2});
  EXPECT_EQ(maxDifference(bake(map, function, {}, one), bake(map, function, {}, two)), 0.0);
}

TEST(Baker, AlphaIsCoverage) {
  const SphereMap map(32);
  const Image image = bake(map, phong(5, Vec3::UnitZ()));
  EXPECT_EQ(image.at(16, 16)[3], 1.0);
  EXPECT_EQ(image.at(0, 0)[3], 0.0);
  EXPECT_NEAR(image.at(31, 16)[3], map.texelCoverage(31, 16), 1e-7);
}

TEST(Baker, FootprintAveragesASharpLobe) {
  // A lobe much narrower than a texel, (r.z)^20000 about the centre of a 16^2 sphere map (a corner
  // of texels (7, 7), (8, 7), (7, 8) and (8, 8)): texel (8, 8) holds the lobe's mean over its
  // footprint. The sphere map is equal-area (dω = 4 ds dt on the disc, s, t in [-1, 1]), with
  // r.z = 1 - 2 (s^2 + t^2) at disc radius sqrt(s^2 + t^2) = sin(theta / 2), so the mean is the
  // plain mean over the texel's square [0, 1/8] x [-1/8, 0] of (1 - 2 (s^2 + t^2))^20000: brute
  // force here on a 4000^2 midpoint grid (the lobe is about 0.005 wide in s and t). Its closed
  // form, the quarter lobe's whole integral pi / (8 (n + 1)) over the square's area 1/64, is
  // 8 pi / (n + 1) = 1.2566e-3.
  const double n = 20000.0;
  const int steps = 4000;
  const double h = 0.125 / steps;
  double sum = 0.0;
  for (int j = 0; j < steps; ++j)
    for (int i = 0; i < steps; ++i) {
      const double s = (i + 0.5) * h, t = (j + 0.5) * h, c = 1.0 - 2.0 * (s * s + t * t);
      sum += std::pow(c, n);
    }
  const double expected = sum / (double(steps) * steps);
  EXPECT_NEAR(expected, 8.0 * kPi / (n + 1.0), 1e-4 * expected);  // the closed form of the same integral
  // With 1 and 16 samples per texel the lobe is narrower than the sample spacing and its exact
  // energy is deposited around its axis (BakeSummary::deltaLobes); 1024 and 4096 samples resolve
  // it. Either way the texel holds the footprint mean, to float precision and the lobe table's
  // 1e-6 tolerance (a point sample at the texel centre would give 2e-137).
  const SphereMap map(16);
  const auto function = phong(n, Vec3::UnitZ());
  for (int samples : {1, 16, 1024, 4096}) {
    BakeOptions options;
    options.samplesPerTexel = samples;
    const auto [image, summary] = bakeMap(map, function, options);
    const double value = image.at(8, 8)[0];
    EXPECT_EQ(summary.deltaLobes, samples <= 16 ? 1 : 0) << samples;
    EXPECT_NEAR(value, expected, 1e-5 * expected) << samples << " samples per texel: " << summary.briefReport();
  }
}

TEST(Baker, RefusesHugeMapsUnlessAllowed) {
  const SphereMap map(16384);
  try {
    bake(map, phong(5, Vec3::UnitZ()));
    FAIL() << "expected a resource error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    EXPECT_NE(std::string(e.what()).find("GiB"), std::string::npos) << e.what();
  }
}

TEST(Baker, ValidatesOptions) {
  const SphereMap map(4);
  BakeOptions options;
  options.samplesPerTexel = 0;
  EXPECT_THROW(bake(map, phong(5, Vec3::UnitZ()), options), Error);
  options.samplesPerTexel = 4;
  EXPECT_THROW(Context({.threads = -1}), Error);
  // 2147483647 threads crashed TBB (SIGSEGV); 70,000 already did. At most 1024.
  try {
    Context({.threads = 2147483647});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument);
    EXPECT_STREQ(e.what(), "threads must be in [0, 1024] (0 = every core), got 2147483647");
  }
  EXPECT_NO_THROW(bake(map, phong(5, Vec3::UnitZ()), options, Context({.threads = 1024})));
}

TEST(Baker, ResolutionOneHoldsTheMeanOverTheDisc) {
  const SphereMap map(1);
  BakeOptions options;
  options.samplesPerTexel = 4096;
  const Image image = bake(map, phong(1, Vec3::UnitZ()), options);
  // Mean of max(0, r_z) over the unit square, r_z = 1 - 2 rho^2 inside the disc, -1 outside:
  // ∫ (1 - 2 rho^2) 2 pi rho drho over rho < 1/sqrt 2 = pi/4, divided by the square's area 4.
  EXPECT_NEAR(image.at(0, 0)[0], kPi / 16, 2e-3);
  EXPECT_NEAR(image.at(0, 0)[3], kPi / 4, 1e-7);  // stored as float
}

TEST(RadialTable, MeetsItsToleranceAgainstTheProfile) {
  for (double n : {1.0, 50.0, 5000.0}) {
    const RadialTable table([n](double c) { return phongLobe(c, n); }, 1e-6);
    EXPECT_LE(table.relativeError(), 1e-6);
    double worst = 0.0;
    for (double c = -1.0; c <= 1.0; c += 1e-4) worst = std::max(worst, std::abs(table.atCos(c) - phongLobe(c, n)));
    EXPECT_LT(worst, 2e-6) << "n = " << n;
  }
}

}  // namespace
}  // namespace brdfbake
