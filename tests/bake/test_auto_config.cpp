// Auto-selection: the chosen configuration meets max_error, and every cheaper one does not.
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <gtest/gtest.h>

namespace brdfbake {
namespace {

struct Case {
  std::string name;
  std::shared_ptr<const Material> material;
  std::vector<DirectionalLight> lights;
};

std::vector<Case> cases() {
  CookTorranceParams copper;
  copper.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  copper.roughness = 0.4;
  return {
      {"phong eye", std::make_shared<PhongMaterial>(Rgb::Ones(), 30.0), {{Vec3::UnitZ(), Rgb::Ones()}}},
      {"phong general", std::make_shared<PhongMaterial>(Rgb::Ones(), 80.0), {{Vec3(1, 1, 1), Rgb::Ones()}}},
      {"blinn exact", std::make_shared<BlinnPhongMaterial>(Rgb::Ones(), 20.0, BlinnConversion::Exact),
       {{Vec3(0, 1, 2), Rgb::Ones()}}},
      {"cook-torrance reflectance", std::make_shared<CookTorranceMaterial>(copper), {}},
  };
}

TEST(AutoConfig, ChoosesTheCheapestConfigurationThatMeetsTheTarget) {
  AutoOptions options;
  options.parameterizations = {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid};
  options.resolutions = {16, 32, 64, 128};
  options.samplesPerTexel = {1, 4};
  options.maxError = 0.01;
  options.error.samples = 4000;
  for (const Case& c : cases()) {
    const MaterialMapFunction function(c.material, c.lights, Vec3::UnitZ());
    const AutoResult result = chooseConfiguration(function, options);
    // Re-measure the chosen configuration from scratch.
    const auto map = makeParameterization(result.chosen.parameterization, result.chosen.resolution);
    BakeOptions bakeOptions;
    bakeOptions.samplesPerTexel = result.chosen.samplesPerTexel;
    const double error = autoErrorMeasure(measureMapError(bake(*map, function, bakeOptions), *map, function, options.error),
                                          result.chosen.parameterization);
    EXPECT_LE(error, options.maxError) << c.name << ": " << result.chosen.describe();
    EXPECT_NEAR(error, result.error, 1e-12) << c.name;
    // Every strictly cheaper configuration misses the target.
    int cheaper = 0;
    for (auto kind : options.parameterizations) {
      for (int n : options.resolutions) {
        for (int spt : options.samplesPerTexel) {
          const MapConfiguration candidate{kind, n, spt};
          if (candidate.cost() >= result.chosen.cost()) continue;
          ++cheaper;
          const auto m = makeParameterization(kind, n);
          BakeOptions o;
          o.samplesPerTexel = spt;
          const double e = autoErrorMeasure(measureMapError(bake(*m, function, o), *m, function, options.error), kind);
          EXPECT_GT(e, options.maxError) << c.name << ": cheaper " << candidate.describe() << " also meets it";
        }
      }
    }
    EXPECT_GT(cheaper, 0) << c.name << " chose the cheapest candidate of all: the test would prove nothing";
  }
}

TEST(AutoConfig, SaysWhatTheBestReachableErrorIsWhenNothingMeetsTheTarget) {
  AutoOptions options;
  options.resolutions = {8, 16};
  options.samplesPerTexel = {1};
  options.maxError = 1e-6;
  options.error.samples = 500;
  const MaterialMapFunction function(std::make_shared<PhongMaterial>(Rgb::Ones(), 50.0), {{Vec3(1, 0, 1), Rgb::Ones()}},
                                     Vec3::UnitZ());
  try {
    chooseConfiguration(function, options);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no configuration meets max_error 1e-06: the best, sphere 16^2"), std::string::npos)
        << e.what();
  }
  options.maxError = 0.0;
  EXPECT_THROW(chooseConfiguration(function, options), Error);
}

}  // namespace
}  // namespace brdfbake
