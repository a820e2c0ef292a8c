// Bake specs: valid specs parse; every bad spec gets an error naming the JSON path.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/spec/spec.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using nlohmann::json;

json validMap() {
  return {{"output", "a.exr"},
          {"parameterization", "sphere"},
          {"resolution", 64},
          {"samples_per_texel", 4},
          {"material", {{"model", "phong"}, {"specular", {1, 1, 1}}, {"exponent", 50}}},
          {"lights", {{{"direction", "eye"}, {"color", {1, 1, 1}}}}}};
}

// The message of the InvalidInput error parsing `document` throws.
std::string errorFor(const json& document) {
  return test::errorOf([&] { parseBakeSpec(document, "/base", "spec.json"); }, Error::Kind::InvalidInput);
}

json withMap(const std::function<void(json&)>& edit) {
  json map = validMap();
  edit(map);
  return {{"maps", {map}}};
}

TEST(Spec, ParsesAValidSpec) {
  const BakeSpec spec = parseBakeSpec({{"maps", {validMap()}}}, "/base", "spec.json");
  ASSERT_EQ(spec.maps.size(), 1u);
  const MapSpec& map = spec.maps[0];
  EXPECT_EQ(map.output, std::filesystem::path("/base/a.exr"));
  EXPECT_EQ(map.resolution, 64);
  EXPECT_EQ(map.samplesPerTexel, 4);
  const MaterialMapSpec* material = map.materialMap();
  ASSERT_NE(material, nullptr);
  EXPECT_EQ(map.environmentMap(), nullptr);
  ASSERT_EQ(material->lights.size(), 1u);
  EXPECT_EQ(material->lights[0].direction, Vec3::UnitZ());  // "eye" is the view vector
  EXPECT_EQ(material->material->model(), "phong");
}

// Values whose formulas would overflow or divide by zero are refused at validation, with their
// JSON path (docs/limits.md), before anything is baked.
TEST(Spec, ParametersOutsideTheirStableRangeAreRefusedWithTheirPath) {
  auto material = [](json m) {
    return [m](json& map) {
      map["material"] = m;
      map.erase("lights");
    };
  };
  const json reflectance = {{"model", "cook_torrance"}, {"mode", "reflectance"}, {"roughness", 0.3}};
  auto withFresnel = [&](const json& fresnel, double roughness = 0.3) {
    json m = reflectance;
    m["fresnel"] = fresnel;
    m["roughness"] = roughness;
    return material(m);
  };
  struct Case {
    std::function<void(json&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases{
      {[](json& m) {
         m["lights"][0]["color"] = {1e308, 1, 1};
       },
       "maps[0].lights[0].color: must be <= 1e+06 per channel (docs/limits.md)"},
      {[](json& m) { m["material"]["specular"] = 2e6; }, "maps[0].material.specular: must be <= 1e+06 per channel"},
      {withFresnel({{"ior", 1e308}}), "maps[0].material.fresnel.ior: must be in [0.001, 1000] (docs/limits.md)"},
      {withFresnel({{"ior", 1.5}}, 5e-324), "maps[0].material.roughness: must be >= 1e-06, got 4.94066e-324"},
      {withFresnel({{"n", 1e155}, {"k", 1e155}}), "maps[0].material.fresnel.n: must be in [0.001, 1000]"},
      {withFresnel({{"n", 1.5}, {"k", 1e155}}), "maps[0].material.fresnel.k: must be in [0, 1000]"},
      {withFresnel({{"spectral", {{"wavelengths_nm", {400, 500}}, {"n", {1, 1e10}}, {"k", {1, 1}}}}}),
       "maps[0].material.fresnel.spectral.n[1]: must be in [0.001, 1000]"},
      {withFresnel({{"spectral", {{"wavelengths_nm", {-400, 500}}, {"f0", {0.5, 0.5}}}}}),
       "maps[0].material.fresnel.spectral.wavelengths_nm[0]: wavelengths must increase strictly, each in (0, 1e5] nm"},
      {[](json& m) { m["resolution"] = 18446744073709551615ull; },
       "maps[0].resolution: must be in [1, 65536], got 18446744073709551615"},
      {[](json& m) { m["output"] = std::string(300, 'o') + ".exr"; },
       "maps[0].output: a name of 304 bytes in the path; file names are limited to 255 (NAME_MAX)"},
      {[](json& m) { m["output"] = std::string("a\x1b[2J.jpg"); },
       "maps[0].output: a\\x1b[2J.jpg: unsupported image extension"},
      {[](json& m) {
         m["lights"] = json::array();
         for (int i = 0; i < 257; ++i) m["lights"].push_back({{"direction", "eye"}});
       },
       "maps[0].lights: at most 256 entries (docs/limits.md), got 257"},
      {[](json& m) {
         json w = json::array(), f0 = json::array();
         for (int i = 0; i < 1025; ++i) w.push_back(300 + i), f0.push_back(0.5);
         m["material"] = {{"model", "fresnel"}, {"fresnel", {{"spectral", {{"wavelengths_nm", w}, {"f0", f0}}}}}};
         m.erase("lights");
       },
       "maps[0].material.fresnel.spectral.wavelengths_nm: at most 1024 entries (docs/limits.md), got 1025"},
  };
  for (const auto& c : cases) {
    const std::string message = errorFor(withMap(c.edit));
    EXPECT_NE(message.find(c.expected), std::string::npos) << "got: " << message << "\nexpected: " << c.expected;
  }
  json many = {{"maps", json::array()}};
  for (int i = 0; i < 1025; ++i) many["maps"].push_back(validMap());
  EXPECT_NE(errorFor(many).find("spec.json: maps: at most 1024 entries (docs/limits.md), got 1025"), std::string::npos);
}

// Keys and values reach messages escaped: "\x1b]0;pwned\x07" as written here, never the bytes.
TEST(Spec, KeysAndValuesInMessagesArePrintable) {
  const std::string hostile = "\x1b]0;pwned\x07\x1b[2J";
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases{
      {[&](json& m) { m[hostile] = 1; }, "maps[0].\\x1b]0;pwned\\x07\\x1b[2J: unknown key"},
      {[&](json& m) { m["parameterization"] = hostile; },
       "parameterization must be one of sphere, paraboloid, cube, latlong, profile, auto; got "
       "\"\\x1b]0;pwned\\x07\\x1b[2J\""},
      {[&](json& m) { m["material"]["model"] = hostile; }, "unknown model '\\x1b]0;pwned\\x07\\x1b[2J'"},
      {[&](json& m) { m["material"]["exponent"] = hostile + std::string(100000, 'e'); },
       "must be a number, got \"\\u001b]0;pwned"},
  };
  for (const auto& [edit, expected] : cases) {
    const std::string message = errorFor(withMap(edit));
    EXPECT_NE(message.find(expected), std::string::npos) << message.substr(0, 300);
    EXPECT_EQ(message.find('\x1b'), std::string::npos);
    EXPECT_LT(message.size(), 600u);
  }
}

TEST(Spec, NamesTheJsonPathOfEveryError) {
  struct Case {
    std::function<void(json&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases{
      {[](json& m) { m["material"]["exponent"] = -3; }, "spec.json: maps[0].material.exponent: must be > 0, got -3"},
      {[](json& m) { m["material"]["exponent"] = "high"; }, "maps[0].material.exponent: must be a number"},
      {[](json& m) { m["material"]["shininess"] = 3; }, "maps[0].material.shininess: unknown key"},
      {[](json& m) { m["colour"] = 3; }, "maps[0].colour: unknown key (known keys: "},
      {[](json& m) { m["samples_per_texle"] = 3; },
       "maps[0].samples_per_texle: unknown key, did you mean "
       "'samples_per_texel'? (known keys: "},
      {[](json& m) { m["material"]["model"] = "lambertian"; }, "maps[0].material.model: unknown model 'lambertian'"},
      {[](json& m) { m["parameterization"] = "spherical"; },
       "maps[0].parameterization: parameterization must be one of sphere, paraboloid, cube, latlong, profile, auto; "
       "got \"spherical\""},
      {[](json& m) { m["resolution"] = 0; }, "maps[0].resolution: must be in [1, 65536], got 0"},
      {[](json& m) { m["resolution"] = 12.5; }, "maps[0].resolution: must be an integer"},
      {[](json& m) { m["samples_per_texel"] = 0; }, "maps[0].samples_per_texel: must be in [1, 4096]"},
      {[](json& m) { m["output"] = "a.jpg"; }, "maps[0].output: "},
      {[](json& m) { m.erase("output"); }, "maps[0].output: required"},
      {[](json& m) {
         m["lights"][0]["direction"] = {0, 0, 0};
       },
       "maps[0].lights[0].direction: must be a non-zero vector"},
      {[](json& m) { m["lights"][0]["direction"] = "sun"; },
       "maps[0].lights[0].direction: must be \"eye\" or [x, y, z]"},
      {[](json& m) {
         m["lights"][0]["color"] = {1, -1, 1};
       },
       "maps[0].lights[0].color: must be >= 0"},
      {[](json& m) {
         m["lights"][0]["color"] = {1, 1};
       },
       "maps[0].lights[0].color: must be [r, g, b]"},
      {[](json& m) { m["lights"] = json::array(); }, "maps[0].lights: phong needs at least one light"},
      {[](json& m) {
         m["view"] = {0, 0, 1};
       },
       "maps[0].view: sphere maps live in eye space"},
      {[](json& m) { m["layout"] = "faces"; }, "maps[0].layout: only applies to cube maps"},
      {[](json& m) { m["parameterization"] = "paraboloid"; },
       "maps[0]: phong lit from the eye depends on the view direction"},
      {[](json& m) {
         m["material"] = {{"model", "blinn_phong"}, {"exponent", 10}, {"phong_exponent", 3}};
       },
       "maps[0].material: give either \"exponent\""},
      {[](json& m) {
         m["material"] = {{"model", "blinn_phong"}, {"phong_exponent", 10}, {"conversion", "5n"}};
       },
       "maps[0].material.conversion: conversion must be one of exact, 4n, fit; got \"5n\""},
  };
  for (const auto& c : cases) {
    const std::string message = errorFor(withMap(c.edit));
    EXPECT_NE(message.find(c.expected), std::string::npos) << "got: " << message << "\nexpected: " << c.expected;
  }
  EXPECT_NE(errorFor({{"maps", json::array()}}).find("maps: must hold at least one map"), std::string::npos);
  EXPECT_NE(errorFor({{"map", json::array()}}).find("maps: required"), std::string::npos);
  EXPECT_NE(errorFor(json::array()).find("(root): must be an object"), std::string::npos);
  EXPECT_NE(errorFor({{"maps", {validMap(), validMap()}}}).find("maps[1].output: same file as maps[0].output"),
            std::string::npos);
}

TEST(Spec, AViewMakesViewDependentMaterialsValidInOtherMaps) {
  json document = withMap([](json& m) {
    m["parameterization"] = "paraboloid";
    m["view"] = {0, 0, 2};
  });
  const BakeSpec spec = parseBakeSpec(document, "/b");
  EXPECT_TRUE(spec.maps[0].viewGiven);
  EXPECT_EQ(spec.maps[0].view, Vec3::UnitZ());
}

TEST(Spec, AutoValuesNeedATargetAndAViewThatFits) {
  const auto autoMap = [](json& m) {
    m["parameterization"] = "auto";
    m["resolution"] = "auto";
    m["samples_per_texel"] = "auto";
    m["max_error"] = 0.01;
    m["lights"] = {{{"direction", {1, 1, 1}}}};
  };
  const BakeSpec spec = parseBakeSpec(withMap(autoMap), "/b");
  ASSERT_TRUE(spec.maps[0].anyAuto());
  const AutoOptions options = spec.maps[0].autoOptions();
  EXPECT_EQ(options.parameterizations.size(), 4u);  // fixed view (default): sphere is a candidate
  EXPECT_EQ(options.maxError, 0.01);
  const BakeSpec free = parseBakeSpec(withMap([&](json& m) {
                                        autoMap(m);
                                        m["view"] = "free";
                                      }),
                                      "/b");
  const auto freeKinds = free.maps[0].autoOptions().parameterizations;
  EXPECT_EQ(std::count(freeKinds.begin(), freeKinds.end(), ParameterizationKind::Sphere), 0);
  EXPECT_EQ(freeKinds.size(), 3u);

  struct Case {
    std::function<void(json&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases{
      {[&](json& m) {
         autoMap(m);
         m.erase("max_error");
       },
       "maps[0].max_error: required with \"auto\" values"},
      {[&](json& m) {
         autoMap(m);
         m["max_error"] = 0;
       },
       "maps[0].max_error: must be > 0"},
      {[&](json& m) {
         autoMap(m);
         m["max_error"] = 1.5;
       },
       "maps[0].max_error: must be <= 1"},
      {[](json& m) { m["max_error"] = 0.01; }, "maps[0].max_error: only applies when"},
      {[](json& m) { m["resolution"] = "big"; }, "maps[0].resolution: must be an integer"},
      {[&](json& m) {
         autoMap(m);
         m["view"] = "moving";
       },
       "maps[0].view: must be \"fixed\", \"free\" or [x, y, z]"},
      {[&](json& m) {
         autoMap(m);
         m["view"] = {0, 0, 1};
       },
       "maps[0].view: with \"parameterization\": \"auto\" give"},
      {[](json& m) { m["view"] = "free"; }, "maps[0].view: a sphere map holds one view"},
      {[&](json& m) {
         autoMap(m);
         m["view"] = "free";
         m["lights"] = {{{"direction", "eye"}}};
       },
       "maps[0].view: phong lit from the eye depends on the view direction, so no environment map can serve a free "
       "view"},
  };
  for (const auto& c : cases) {
    const std::string message = errorFor(withMap(c.edit));
    EXPECT_NE(message.find(c.expected), std::string::npos) << "got: " << message << "\nexpected: " << c.expected;
  }
}

TEST(Spec, FileErrorsNameFileLineAndColumn) {
  test::TempDir dir;
  const auto path = dir / "broken.json";
  std::ofstream(path) << "{\n  \"maps\": [\n    {\"output\": \"a.exr\",,}\n  ]\n}\n";
  try {
    loadBakeSpec(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":3:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadBakeSpec(dir / "absent.json"), Error);
}

TEST(Spec, RelativeOutputsResolveAgainstTheSpecFolder) {
  test::TempDir dir;
  std::ofstream(dir / "s.json") << json{{"maps", {validMap()}}}.dump();
  const BakeSpec spec = loadBakeSpec(dir / "s.json");
  EXPECT_EQ(spec.maps[0].output, dir.path() / "a.exr");
}

TEST(Spec, EverySampleSpecParses) {
  // What each sample spec in data_samples/specs/ asks for, typed from the files: per map its
  // output, its model (or "environment:" and the lobe), parameterization ("auto" when the tool
  // picks; "profile" for 1-D profiles), resolution (0 when auto) and number of lights.
  struct Expected {
    std::string output, model, parameterization;
    int resolution;
    std::size_t lights;
  };
  const std::map<std::string, std::vector<Expected>> expected{
      {"auto.json", {{"phong_auto_fixed.exr", "phong", "auto", 0, 2}, {"phong_auto_free.exr", "phong", "auto", 0, 2}}},
      {"blinn_phong.json",
       {{"blinn_exact.exr", "blinn_phong", "sphere", 256, 1},
        {"blinn_4n.exr", "blinn_phong", "sphere", 256, 1},
        {"blinn_diffuse_paraboloid.exr", "blinn_phong", "paraboloid", 128, 2}}},
      {"colorgram.json",
       {{"colorgram.exr", "colorgram", "sphere", 256, 0}, {"colorgram.png", "colorgram", "sphere", 256, 0}}},
      {"copper.json",
       {{"copper_reflectance.exr", "cook_torrance", "sphere", 256, 0},
        {"copper_sphere.png", "cook_torrance", "sphere", 256, 0},
        {"copper_lighting.exr", "cook_torrance", "sphere", 256, 1}}},
      {"fresnel.json",
       {{"fresnel_copper.exr", "fresnel", "sphere", 256, 0}, {"fresnel_glass.exr", "fresnel", "sphere", 256, 0}}},
      {"gooch.json", {{"gooch.png", "gooch", "sphere", 256, 0}}},
      {"hatching.json", {{"hatching.png", "hatching", "sphere", 256, 0}}},
      {"measured_lobes.json",
       {{"measured_lobes_reflectance.exr", "lobes", "sphere", 256, 0},
        {"measured_lobes_reflectance.png", "lobes", "sphere", 256, 0},
        {"measured_lobes_lighting.exr", "lobes", "paraboloid", 256, 1},
        {"measured_lobes_prefiltered.exr", "lobes", "paraboloid", 256, 1}}},
      {"measured_mirror.json",
       {{"measured_mirror_seed.exr", "measured", "sphere", 256, 0},
        {"measured_mirror_fit.exr", "measured", "sphere", 256, 0}}},
      {"phong_diffuse.json", {{"phong_diffuse.exr", "phong", "sphere", 256, 2}}},
      {"phong_eye.json",
       {{"phong_eye.exr", "phong", "sphere", 256, 1}, {"phong_paraboloid.exr", "phong", "paraboloid", 256, 1}}},
      {"plastic.json",
       {{"plastic_reflectance.exr", "cook_torrance", "sphere", 256, 0},
        {"plastic_lighting.exr", "cook_torrance", "sphere", 256, 1},
        {"plastic_paraboloid.exr", "cook_torrance", "paraboloid", 128, 1}}},
      {"prefilter_decomposition.json",
       {{"sky_varying_lobes_paraboloid.exr", "environment:lobes:../fits/synthetic_varying.json", "paraboloid", 64, 0},
        {"sky_coat_sphere.exr", "environment:mirror", "sphere", 128, 0}}},
      {"prefilter_fitted.json",
       {{"sky_fitted_lobes_paraboloid.exr", "environment:lobes:../fits/synthetic_two_lobes.json", "paraboloid", 64,
         0}}},
      {"prefilter_sky.json",
       {{"sky_phong100_paraboloid.exr", "environment:phong:100", "paraboloid", 128, 0},
        {"sky_ggx040_cube.exr", "environment:ggx:0.4", "cube", 64, 0},
        {"sky_irradiance_sphere.exr", "environment:irradiance", "sphere", 64, 0},
        {"colored_cube_mirror_sphere.exr", "environment:mirror", "sphere", 128, 0}}},
      {"profile.json",
       {{"copper_auto.exr", "cook_torrance", "auto", 0, 0}, {"phong_eye_profile.exr", "phong", "profile", 256, 1}}},
      {"silhouette.json", {{"silhouette.exr", "silhouette", "sphere", 256, 0}}},
  };
  std::set<std::string> seen;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourcePath("data_samples/specs"))) {
    if (entry.path().extension() != ".json") continue;
    const std::string name = entry.path().filename().string();
    seen.insert(name);
    const auto it = expected.find(name);
    if (it == expected.end()) {
      ADD_FAILURE() << name << ": a sample spec this test does not know; add what it asks for to the table above";
      continue;
    }
    BakeSpec spec;
    ASSERT_NO_THROW(spec = loadBakeSpec(entry.path())) << name;
    ASSERT_EQ(spec.maps.size(), it->second.size()) << name;
    for (std::size_t i = 0; i < spec.maps.size(); ++i) {
      const MapSpec& map = spec.maps[i];
      const Expected& e = it->second[i];
      SCOPED_TRACE(name + " maps[" + std::to_string(i) + "]");
      EXPECT_EQ(map.output, entry.path().parent_path() / e.output);
      if (e.model.rfind("environment:", 0) == 0) {
        ASSERT_NE(map.environmentMap(), nullptr);
        EXPECT_EQ("environment:" + map.environmentMap()->lobeName, e.model);
        EXPECT_EQ(map.materialMap(), nullptr);
        EXPECT_EQ(e.lights, 0u);
      } else {
        const MaterialMapSpec* material = map.materialMap();
        ASSERT_NE(material, nullptr);
        EXPECT_EQ(map.environmentMap(), nullptr);
        // A measured material's fit is deferred to prepare(): then there is no material yet.
        EXPECT_NE(material->material == nullptr, !material->deferredFit.has_value());
        EXPECT_EQ(map.modelName(), e.model);
        EXPECT_EQ(material->lights.size(), e.lights);
      }
      if (e.parameterization == "auto") {
        EXPECT_TRUE(map.autoSelect.parameterization);
        EXPECT_TRUE(map.autoSelect.resolution);
      } else {
        EXPECT_FALSE(map.autoSelect.parameterization);
        EXPECT_EQ(map.radialProfile, e.parameterization == "profile");
        EXPECT_EQ(std::string(toString(map.parameterization)),
                  e.parameterization == "profile" ? "sphere" : e.parameterization);
        EXPECT_EQ(map.resolution, e.resolution);
      }
    }
  }
  EXPECT_EQ(seen.size(), expected.size()) << "a sample spec listed here is missing from data_samples/specs";
}

// Parsing a spec parses it: a "measured" material's fit runs in MapSpec::prepare, with progress,
// and the rules that need the fitted material are checked there.
TEST(Spec, MeasuredFitsRunWhenTheMapIsPreparedNotWhileParsing) {
  BakeSpec spec = loadBakeSpec(test::sourcePath("data_samples/specs/measured_mirror.json"));
  MapSpec& map = spec.maps[1];
  const MaterialMapSpec& material = *map.materialMap();
  ASSERT_TRUE(material.deferredFit.has_value());
  EXPECT_EQ(material.material, nullptr);
  EXPECT_EQ(material.deferredFit->jsonPath, "maps[1].material");
  EXPECT_GT(material.deferredFit->table.size(), 100u);  // read and checked while parsing
  EXPECT_THROW(map.makeFunction(), Error);
  std::vector<double> progress;
  map.prepare(Context({.progress = [&](const std::string&, double fraction) { progress.push_back(fraction); }}));
  ASSERT_NE(material.material, nullptr);
  EXPECT_FALSE(material.deferredFit.has_value());
  EXPECT_EQ(map.modelName(), "measured");
  ASSERT_FALSE(progress.empty());
  EXPECT_GT(progress.back(), 0.5);  // fitLobes reports per solve; the last solves may be skipped
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  // Reflectance mode: the map is the fitted BRDF on the mirror direction, positive at the centre.
  const Rgb centre = map.makeFunction()->evaluate(Vec3::UnitZ());
  EXPECT_TRUE(centre.allFinite());
  EXPECT_GT(centre.minCoeff(), 0.0);
  map.prepare();  // nothing pending: a no-op
  EXPECT_EQ(map.modelName(), "measured");
}

TEST(Spec, RulesThatNeedTheFittedMaterialAreCheckedWhenItIsMade) {
  // Fitted lobes lit by two lights have no common axis: no profile. Known only after the fit.
  nlohmann::json document = {{"maps",
                              {{{"output", "a.exr"},
                                {"parameterization", "profile"},
                                {"resolution", 64},
                                {"samples_per_texel", 1},
                                {"material",
                                 {{"model", "measured"},
                                  {"file", test::sourcePath("data_samples/tables/synthetic_varying.astm")},
                                  {"method", "fit"},
                                  {"lobes", 1},
                                  {"elevation", "constant"},
                                  {"mode", "prefiltered"}}},
                                {"lights", {{{"direction", {0, 0, 1}}}, {{"direction", {1, 0, 1}}}}}}}}};
  BakeSpec spec = parseBakeSpec(document, "/base", "s.json");
  try {
    spec.maps[0].prepare();
    FAIL() << "a profile of two lights' lobes was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("s.json: maps[0].parameterization: a profile needs a map radially symmetric"),
              std::string::npos)
        << e.what();
  }
  // A mode that uses lights without any is refused while parsing, before any fit.
  document["maps"][0].erase("lights");
  EXPECT_THROW(parseBakeSpec(document, "/base", "s.json"), Error);
}

}  // namespace
}  // namespace brdfbake
