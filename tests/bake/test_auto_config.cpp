// Auto-selection: the chosen configuration meets max_error, and every cheaper one does not.
#include <gtest/gtest.h>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>

#include <algorithm>
#include <optional>
#include <string>

#include "test_support.hpp"

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
      {"blinn exact",
       std::make_shared<BlinnPhongMaterial>(Rgb::Ones(), 20.0, BlinnConversion::Exact),
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
    const double error =
        autoErrorMeasure(measureMapError(bake(*map, function, bakeOptions), *map, function, options.error),
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
    EXPECT_NE(std::string(e.what()).find("no configuration meets max_error 1e-06: the best, sphere 16^2"),
              std::string::npos)
        << e.what();
  }
  options.maxError = 0.0;
  EXPECT_THROW(chooseConfiguration(function, options), Error);
}

// Narrow and wide lobes over every parameterization, resolution and sample count: at most three
// bakes each, progress reported and ending at 1, the chosen map re-measured meets the bound and
// its kind at half the resolution, baked and measured here, misses it.
TEST(AutoConfig, BakesAtMostThreeMapsPerChoiceWithProgress) {
  CookTorranceParams ct;
  ct.mode = CookTorranceMode::Lighting;
  ct.roughness = 0.05;
  ct.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  const std::vector<DirectionalLight> light{{Vec3(0.2, 0.5, 1.0).normalized(), Rgb::Ones()}};
  std::vector<Case> models;
  for (double n : {10.0, 200.0, 1000.0, 10000.0})
    models.push_back({"phong " + std::to_string(int(n)), std::make_shared<PhongMaterial>(Rgb::Ones(), n), light});
  models.push_back({"cook-torrance m = 0.05", std::make_shared<CookTorranceMaterial>(ct), light});
  AutoOptions options;
  options.parameterizations = {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid,
                               ParameterizationKind::Cube, ParameterizationKind::LatLong};
  options.maxError = 0.005;
  options.error.samples = 5000;
  for (const Case& c : models) {
    const MaterialMapFunction function(c.material, c.lights, Vec3::UnitZ());
    std::vector<double> progress;
    const Context context({.progress = [&](const std::string&, double f) { progress.push_back(f); }});
    const AutoResult result = chooseConfiguration(function, options, context);
    EXPECT_GE(result.bakes, 1) << c.name;
    EXPECT_LE(result.bakes, 3) << c.name;
    EXPECT_GT(result.estimated, 0) << c.name;
    ASSERT_GE(progress.size(), 3u) << c.name;
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << c.name;
    EXPECT_EQ(progress.back(), 1.0) << c.name;
    // Re-measured from scratch (a new bake, new probes).
    auto measured = [&](const MapConfiguration& configuration) {
      const auto map = makeParameterization(configuration.parameterization, configuration.resolution);
      BakeOptions bakeOptions;
      bakeOptions.samplesPerTexel = configuration.samplesPerTexel;
      return autoErrorMeasure(measureMapError(bake(*map, function, bakeOptions), *map, function, options.error),
                              configuration.parameterization);
    };
    EXPECT_NEAR(measured(result.chosen), result.error, 1e-12) << c.name;
    EXPECT_LE(result.error, options.maxError) << c.name;
    ASSERT_GT(result.chosen.resolution, 16) << c.name;
    const MapConfiguration half{result.chosen.parameterization, result.chosen.resolution / 2,
                                result.chosen.samplesPerTexel};
    EXPECT_GT(measured(half), options.maxError) << c.name << ": " << half.describe();
    std::cout << c.name << ": " << result.chosen.describe() << ", " << result.bakes << " bake(s), " << result.estimated
              << " estimates\n";
  }
}

TEST(AutoConfig, AnUnreachableBoundSaysWhatItWouldTake) {
  const MaterialMapFunction function(std::make_shared<PhongMaterial>(Rgb::Ones(), 10000.0),
                                     {{Vec3(0.2, 0.5, 1.0).normalized(), Rgb::Ones()}}, Vec3::UnitZ());
  AutoOptions options;
  options.resolutions = {16, 32, 64, 128, 256};
  options.maxError = 0.005;
  options.error.samples = 5000;
  std::vector<double> progress;
  const Context context({.progress = [&](const std::string&, double f) { progress.push_back(f); }});
  try {
    chooseConfiguration(function, options, context);
    FAIL() << "a 256^2 sphere map cannot hold a Phong 10000 lobe to 0.5 %";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("no configuration meets max_error 0.005: the best, sphere 256^2"), std::string::npos)
        << message;
    // error ~ N^-2 from 256^2: the 2048^2 sphere map meets 0.5 % (0.29 % measured, docs/accuracy.md)
    // and 1024^2 misses it (1.1 %), so the resolution it names lies between.
    const std::string about = "that takes about sphere ";
    const auto at = message.find(about);
    ASSERT_NE(at, std::string::npos) << message;
    const int needed = std::stoi(message.substr(at + about.size()));
    EXPECT_GT(needed, 1024) << message;
    EXPECT_LE(needed, 4096) << message;
  }
  EXPECT_FALSE(progress.empty()) << "the search reported no progress";
  // Past the memory budget: said so.
  options.resolutions = {16, 32, 64, 128, 256, 512, 1024, 2048};
  std::optional<test::EnvironmentVariable> budget;
  budget.emplace("BRDFBAKE_MEMORY_LIMIT", "1M");  // 256^2 float RGBA texels
  try {
    chooseConfiguration(function, options);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the best, sphere 256^2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("exceed the memory budget"), std::string::npos) << e.what();
  }
  budget.reset();
  budget.emplace("BRDFBAKE_MEMORY_LIMIT", "1600");  // 100 texels
  try {
    chooseConfiguration(function, options);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    EXPECT_NE(std::string(e.what()).find("every auto candidate exceeds the memory budget"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace brdfbake
