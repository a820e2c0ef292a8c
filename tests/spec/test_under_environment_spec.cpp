// Materials lit by an environment in specs ("material" beside "environment"; docs/matcap.md): what
// parses into what, every bad input named by its JSON path, and the map made from the parsed spec.
#include <gtest/gtest.h>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/spec/spec.hpp>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using nlohmann::json;

const std::filesystem::path kSamples = std::filesystem::path(BRDFBAKE_SOURCE_DIR) / "data_samples";

json copperUnderSky() {
  return {{"output", "copper.exr"},
          {"parameterization", "sphere"},
          {"resolution", 32},
          {"samples_per_texel", 4},
          {"material",
           {{"model", "cook_torrance"},
            {"distribution", "ggx"},
            {"roughness", 0.3},
            {"fresnel", {{"schlick", {0.955, 0.638, 0.538}}}},
            {"shadowing", "smith_separable"}}},
          {"environment", {{"file", "environments/sky_latlong.exr"}, {"max_error", 0.02}}},
          {"camera", {{"forward", {0, 0, -1}}, {"up", {0, 1, 0}}}}};
}

BakeSpec parse(const json& map) { return parseBakeSpec({{"maps", {map}}}, kSamples, "spec.json"); }

// The message of the InvalidInput error parsing `map` throws.
std::string errorFor(const json& map) {
  return test::errorOf([&] { parse(map); }, Error::Kind::InvalidInput);
}

TEST(UnderEnvironmentSpec, AMaterialBesideAnEnvironmentIsLitByIt) {
  const BakeSpec spec = parse(copperUnderSky());
  const MapSpec& map = spec.maps[0];
  ASSERT_NE(map.materialMap(), nullptr);
  EXPECT_EQ(map.environmentMap(), nullptr);
  const EnvironmentLighting* lighting = map.environmentLighting();
  ASSERT_NE(lighting, nullptr);
  EXPECT_EQ(lighting->file, kSamples / "environments/sky_latlong.exr");
  EXPECT_EQ(lighting->maxError, 0.02);
  const auto* ct = dynamic_cast<const CookTorranceMaterial*>(map.materialMap()->material.get());
  ASSERT_NE(ct, nullptr);
  EXPECT_EQ(ct->params().mode, CookTorranceMode::Lighting) << "mode defaults to lighting under an environment";
  EXPECT_EQ(ct->params().shadowing, MicrofacetShadowing::SmithSeparable);
  const UnderEnvironmentOptions options = map.underEnvironmentOptions();
  EXPECT_EQ(options.resolution, 32);
  EXPECT_EQ(options.samplesPerTexel, 4);
  EXPECT_EQ(options.maxError, 0.02);
  EXPECT_EQ(options.camera.forward, Vec3(0, 0, -1));
  ASSERT_EQ(map.inputs.size(), 1u);
  EXPECT_EQ(map.inputs[0].role, "maps[0].environment.file");
  EXPECT_THROW(map.makeFunction(), Error) << "bakeUnderEnvironment makes it, not the baker";

  // A fitted model without "mode" is lit through its BRDF (lighting); yaw and pitch turn the camera.
  json lobes = copperUnderSky();
  lobes["material"] = {{"model", "lobes"}, {"file", "fits/synthetic_two_lobes.json"}};
  lobes["camera"] = {{"yaw", 90}, {"pitch", 10}};
  const BakeSpec fitted = parse(lobes);
  const auto* material = dynamic_cast<const LobeMaterial*>(fitted.maps[0].materialMap()->material.get());
  ASSERT_NE(material, nullptr);
  EXPECT_EQ(material->mode(), LobeMaterialMode::Lighting);
  EXPECT_NEAR(fitted.maps[0].environmentLighting()->camera.forward.x(), std::cos(radians(10.0)), 1e-12);
  // A measured table is fitted (deferred) in lighting mode.
  json measured = copperUnderSky();
  measured["material"] = {{"model", "measured"}, {"file", "tables/synthetic_two_lobes.astm"}, {"method", "fit"}};
  const BakeSpec deferred = parse(measured);
  ASSERT_TRUE(deferred.maps[0].materialMap()->deferredFit);
  EXPECT_EQ(deferred.maps[0].materialMap()->deferredFit->mode, LobeMaterialMode::Lighting);
}

TEST(UnderEnvironmentSpec, BadInputNamesItsJsonPath) {
  struct Case {
    std::function<void(json&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases{
      {[](json& m) {
         m["material"] = {{"model", "gooch"}};
       },
       "maps[0].material: gooch has no BRDF"},
      {[](json& m) {
         m["material"] = {{"model", "silhouette"}, {"width", 20}};
       },
       "maps[0].material: silhouette has no BRDF"},
      {[](json& m) { m["material"]["mode"] = "reflectance"; },
       "maps[0].material.mode: a material lit by an environment"},
      {[](json& m) {
         m["material"] = {{"model", "lobes"}, {"file", "fits/synthetic_two_lobes.json"}, {"mode", "prefiltered"}};
       },
       "maps[0].material.mode: a material lit by an environment"},
      {[](json& m) {
         m["material"] = {{"model", "measured"}, {"file", "tables/synthetic_two_lobes.astm"}, {"method", "mirror"}};
       },
       "maps[0].material.method: a material lit by an environment needs a BRDF"},
      {[](json& m) { m["material"]["shadowing"] = "smith"; }, "maps[0].material.shadowing: shadowing must be one of"},
      {[](json& m) {
         m["camera"]["up"] = {0, 1, 0.1};
       },
       "maps[0].camera: camera up [0, 1, 0.1] is not a unit vector"},
      {[](json& m) {
         m["camera"]["up"] = {0, 0.6, 0.8};
       },
       "maps[0].camera: camera forward [0, 0, -1] and up"},
      {[](json& m) { m["camera"]["yaw"] = 10; }, "maps[0].camera: give either"},
      {[](json& m) {
         m["camera"] = {{"pitch", 100}};
       },
       "maps[0].camera.pitch: must be <= 90, got 100"},
      {[](json& m) {
         m["camera"]["forward"] = {0, "a", 1};
       },
       "maps[0].camera.forward[1]: must be a number"},
      {[](json& m) {
         m["lights"] = json::array({{{"direction", "eye"}}});
       },
       "maps[0].lights: a material lit by"},
      {[](json& m) { m["environment"]["lobe"] = "phong:100"; }, "maps[0].environment.lobe: with a \"material\""},
      {[](json& m) { m["environment"]["mips"] = true; }, "maps[0].environment.mips: unknown key"},
      {[](json& m) { m["environment"]["file"] = ""; }, "maps[0].environment.file: must not be empty"},
      {[](json& m) { m["environment"]["method"] = "fast"; }, "maps[0].environment.method: method must be one of"},
      {[](json& m) { m["environment"]["max_error"] = 0.9; }, "maps[0].environment.max_error: must be <= 0.5"},
      {[](json& m) { m["environment"]["max_relative_error"] = 0; },
       "maps[0].environment.max_relative_error: must be > 0"},
      {[](json& m) { m["parameterization"] = "profile"; }, "maps[0].parameterization: a material lit by"},
      {[](json& m) { m["resolution"] = "auto"; }, "maps[0].max_error: required with \"auto\" values"},
      {[](json& m) {
         m["view"] = {0, 1, 1};
       },
       "maps[0].view: sphere maps live in eye space"},
      {[](json& m) { m["fresnel_table_output"] = "f.exr"; }, "maps[0].fresnel_table_output: unknown key"},
  };
  for (const auto& c : cases) {
    json map = copperUnderSky();
    c.edit(map);
    const std::string message = errorFor(map);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "got: " << message << "\nexpected: " << c.expected;
  }
  // "camera" belongs to maps lit by an environment.
  json lit = copperUnderSky();
  lit.erase("environment");
  lit["lights"] = json::array({{{"direction", "eye"}}});
  lit["material"]["mode"] = "lighting";
  EXPECT_NE(errorFor(lit).find("maps[0].camera: unknown key"), std::string::npos) << errorFor(lit);
}

TEST(UnderEnvironmentSpec, TheEnvironmentIsCheckedBeforeAnyWorkWithItsJsonPath) {
  test::TempDir dir;
  { std::ofstream(dir / "notes.exr") << "not an image"; }
  for (const std::string& file : {std::string("missing.exr"), std::string("notes.exr")}) {
    json map = copperUnderSky();
    map["environment"]["file"] = file;
    const BakeSpec spec = parseBakeSpec({{"maps", {map}}}, dir.path(), "spec.json");
    try {
      loadMapEnvironment(spec.maps[0]);
      ADD_FAILURE() << file << " was read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("spec.json: maps[0].environment.file: "), std::string::npos) << e.what();
    }
  }
}

TEST(UnderEnvironmentSpec, TheMapIsMadeFromTheParsedSpec) {
  // A white Lambertian (Phong's diffuse) in the furnace shows its albedo; the map is written with its
  // metadata and reads back.
  json map = copperUnderSky();
  map["material"] = {{"model", "phong"}, {"specular", 0}, {"exponent", 1}, {"diffuse", 0.5}};
  map["environment"]["file"] = "environments/furnace_latlong.exr";
  const BakeSpec spec = parse(map);
  const Environment environment = loadMapEnvironment(spec.maps[0]);
  const MaterialUnderEnvironment result = bakeUnderEnvironment(spec.maps[0], environment, test::twoThreads());
  EXPECT_NEAR(result.image.at(16, 16)[0], 0.5, 0.0025);
  test::TempDir dir;
  writeUnderEnvironmentMap(result, dir / "furnace.exr", spec.maps[0].raw);
  const MapFile file = readMap(dir / "furnace.exr");
  EXPECT_EQ(file.info.resolution, 32);
  EXPECT_EQ(file.info.spec["under_environment"]["material"], "phong");
  // A furnace's Lambertian matcap is 0.5 everywhere: every texel is above 1 % of the median, and
  // within 0.5 % of it (the check above), so the relative error recorded is at most that.
  EXPECT_DOUBLE_EQ(file.info.spec["under_environment"]["max_relative_error"].get<double>(), 0.06);  // 3 x 0.02
  EXPECT_LT(file.info.spec["under_environment"]["relative_error"].get<double>(), 0.005);
  EXPECT_NEAR(file.image.at(16, 16)[0], 0.5, 0.0025);
  // Not for other maps.
  json lit = copperUnderSky();
  lit.erase("environment");
  lit.erase("camera");
  lit["lights"] = json::array({{{"direction", "eye"}}});
  lit["material"]["mode"] = "lighting";
  const BakeSpec plain = parse(lit);
  EXPECT_THROW(bakeUnderEnvironment(plain.maps[0], environment), Error);
  EXPECT_THROW(loadMapEnvironment(plain.maps[0]), Error);
}

}  // namespace
}  // namespace brdfbake
