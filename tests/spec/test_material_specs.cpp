// Specs of the cook_torrance, fresnel, colorgram, gooch, silhouette and hatching models: valid ones
// parse into the right materials; every bad one gets an error naming its JSON path.
#include <gtest/gtest.h>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/spec/spec.hpp>

#include <complex>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using nlohmann::json;

json mapWith(const json& material, const json& extra = json::object()) {
  json map = {{"output", "a.exr"},
              {"parameterization", "sphere"},
              {"resolution", 64},
              {"samples_per_texel", 4},
              {"material", material}};
  for (const auto& [key, value] : extra.items()) map[key] = value;
  return map;
}

json cookTorrance() {
  return {{"model", "cook_torrance"},  {"mode", "reflectance"},  {"distribution", "beckmann"}, {"roughness", 0.3},
          {"fresnel", {{"ior", 1.5}}}, {"specular_weight", 1.0}, {"diffuse", {0.0, 0.0, 0.0}}};
}

json colorgram() {
  return {{"model", "colorgram"},
          {"stops", {{{"angle", 0}, {"color", {1, 1, 1}}}, {{"angle", 60}, {"color", {1, 0, 0}}}}},
          {"blur", 2},
          {"twist", 15},
          {"blend", "modulate"}};
}

BakeSpec parse(const json& map) { return parseBakeSpec({{"maps", {map}}}, "/base", "spec.json"); }

// The message of the InvalidInput error parsing `map` throws.
std::string errorFor(const json& map) {
  return test::errorOf([&] { parse(map); }, Error::Kind::InvalidInput);
}

TEST(MaterialSpecs, ContractExamplesParse) {
  // The three examples of the spec contract, verbatim.
  const auto ct = parse(mapWith(cookTorrance()));
  const auto* m = dynamic_cast<const CookTorranceMaterial*>(ct.maps[0].materialMap()->material.get());
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->params().mode, CookTorranceMode::Reflectance);
  EXPECT_NEAR(m->params().fresnel.f0()[0], 0.04, 1e-15);
  EXPECT_EQ(m->params().normalization, CookTorranceNormalization::Microfacet);  // the default
  EXPECT_FALSE(m->usesLights());

  const auto fr = parse(mapWith({{"model", "fresnel"}, {"fresnel", {{"f0", {0.955, 0.638, 0.538}}}}}));
  const auto* f = dynamic_cast<const FresnelMaterial*>(fr.maps[0].materialMap()->material.get());
  ASSERT_NE(f, nullptr);
  EXPECT_NEAR(f->fresnel().f0()[1], 0.638, 1e-12);
  EXPECT_EQ(f->combine(), FresnelCombine::Add);

  const auto cg = parse(mapWith(colorgram()));
  const auto* c = dynamic_cast<const ColorgramMaterial*>(cg.maps[0].materialMap()->material.get());
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->blend(), ColorgramBlend::Modulate);
  EXPECT_EQ(c->twist(), 15.0);
  EXPECT_EQ(cg.maps[0].raw["material"]["blend"], "modulate");  // recorded in the map's metadata
}

// Unpolarised Fresnel reflectance for a complex index eta = n + i k (k = 0: a dielectric) at
// cos theta = c, from the s and p amplitudes with complex Snell's law, typed out.
double fresnelByHand(double c, double n, double k) {
  const std::complex<double> eta(n, k);
  const std::complex<double> ct = std::sqrt(1.0 - (1.0 - c * c) / (eta * eta));
  const std::complex<double> rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

TEST(MaterialSpecs, FresnelForms) {
  auto fresnelOf = [](const json& f) {
    json m = cookTorrance();
    m["fresnel"] = f;
    const BakeSpec spec = parse(mapWith(m));
    const auto* material = dynamic_cast<const CookTorranceMaterial*>(spec.maps[0].materialMap()->material.get());
    EXPECT_NE(material, nullptr);
    return material->params().fresnel;
  };
  // Conductor n + i k: F(1) = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2), F(0) = 1, and in between the
  // complex amplitudes.
  const double n[3] = {0.22, 1.02, 1.24}, k[3] = {3.747, 2.577, 2.397};
  const FresnelTerm nk = fresnelOf({{"n", {0.22, 1.02, 1.24}}, {"k", {3.747, 2.577, 2.397}}});
  EXPECT_NEAR(nk.f0()[0], 0.9433, 1e-4);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(nk(1.0)[c], ((n[c] - 1) * (n[c] - 1) + k[c] * k[c]) / ((n[c] + 1) * (n[c] + 1) + k[c] * k[c]), 1e-12)
        << c;
    EXPECT_NEAR(nk(0.0)[c], 1.0, 1e-12) << c;
    EXPECT_NEAR(nk(0.5)[c], fresnelByHand(0.5, n[c], k[c]), 1e-12) << c;
  }
  // Dielectric per channel: F(1) = ((eta - 1) / (eta + 1))^2, F(0) = 1.
  const double eta[3] = {1.5, 1.6, 1.7};
  const FresnelTerm ior = fresnelOf({{"ior", {1.5, 1.6, 1.7}}});
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(ior(1.0)[c], std::pow((eta[c] - 1) / (eta[c] + 1), 2), 1e-12) << c;
    EXPECT_NEAR(ior(0.0)[c], 1.0, 1e-12) << c;
    EXPECT_NEAR(ior(0.5)[c], fresnelByHand(0.5, eta[c], 0.0), 1e-12) << c;
  }
  EXPECT_NEAR(ior(1.0)[0], 0.04, 1e-15);
  // Spectral n + i k and spectral f0 (docs: each wavelength's reflectance, to linear sRGB, divided
  // by a constant 1's RGB, clamped to [0, 1]). At normal incidence the spectrum is the conductor
  // F(1) formula per wavelength (or f0 itself); at grazing incidence every wavelength reflects 1,
  // so F(0) = 1 exactly.
  const std::vector<double> nm{450, 550, 650}, sn{1.24, 1.02, 0.22}, sk{2.4, 2.58, 3.75}, sf0{0.5, 0.6, 0.9};
  std::vector<double> spectralF0(3);
  for (int j = 0; j < 3; ++j)
    spectralF0[j] = ((sn[j] - 1) * (sn[j] - 1) + sk[j] * sk[j]) / ((sn[j] + 1) * (sn[j] + 1) + sk[j] * sk[j]);
  const Rgb white = spectrumToLinearSrgb(nm, std::vector<double>{1, 1, 1});
  const Rgb expectedNk = (spectrumToLinearSrgb(nm, spectralF0) / white).min(1.0).max(0.0);
  const Rgb expectedF0 = (spectrumToLinearSrgb(nm, sf0) / white).min(1.0).max(0.0);
  const FresnelTerm spectralNk = fresnelOf(
      {{"spectral", {{"wavelengths_nm", {450, 550, 650}}, {"n", {1.24, 1.02, 0.22}}, {"k", {2.4, 2.58, 3.75}}}}});
  const FresnelTerm spectralFromF0 =
      fresnelOf({{"spectral", {{"wavelengths_nm", {450, 550, 650}}, {"f0", {0.5, 0.6, 0.9}}}}});
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(spectralNk(1.0)[c], expectedNk[c], 1e-9) << c;
    EXPECT_NEAR(spectralNk(0.0)[c], 1.0, 1e-12) << c;
    EXPECT_NEAR(spectralFromF0(1.0)[c], expectedF0[c], 1e-9) << c;
    EXPECT_NEAR(spectralFromF0(0.0)[c], 1.0, 1e-12) << c;
  }
  // Copper-like (red reflects most) and a f0 rising to the red: red is the largest channel.
  EXPECT_GT(spectralNk(1.0)[0], spectralNk(1.0)[2]);
  EXPECT_GT(spectralFromF0(1.0)[0], spectralFromF0(1.0)[2]);
}

TEST(MaterialSpecs, NamesTheJsonPathOfEveryError) {
  struct Case {
    json map;
    std::string expected;
  };
  auto ct = [](const std::function<void(json&)>& edit) {
    json m = cookTorrance();
    edit(m);
    return mapWith(m);
  };
  auto cg = [](const std::function<void(json&)>& edit) {
    json m = colorgram();
    edit(m);
    return mapWith(m);
  };
  const std::vector<Case> cases{
      {ct([](json& m) { m.erase("mode"); }), "maps[0].material.mode: required"},
      {ct([](json& m) { m["mode"] = "mirror"; }),
       "maps[0].material.mode: mode must be one of lighting, reflectance; got \"mirror\""},
      {ct([](json& m) { m["distribution"] = "phong"; }),
       "maps[0].material.distribution: distribution must be one of beckmann, ggx"},
      {ct([](json& m) { m["roughness"] = 0; }), "maps[0].material.roughness: must be >= 1e-06, got 0"},
      {ct([](json& m) { m["roughness"] = 20; }), "maps[0].material.roughness: must be <= 10, got 20"},
      {ct([](json& m) { m["specular_weight"] = 1.5; }), "maps[0].material.specular_weight: must be <= 1"},
      {ct([](json& m) {
         m["diffuse"] = {0.5, 0.1, 0.1};
       }),
       "maps[0].material.diffuse: must be 0 in reflectance mode"},
      {ct([](json& m) {
         m["diffuse"] = {2, 0, 0};
       }),
       "maps[0].material.diffuse: is an albedo and must be <= 1"},
      {ct([](json& m) { m["normalization"] = "1982"; }), "maps[0].material.normalization: normalization must be"},
      {ct([](json& m) { m["grazing_angle"] = 90; }), "maps[0].material.grazing_angle: must be < 90"},
      {ct([](json& m) { m["shininess"] = 3; }), "maps[0].material.shininess: unknown key"},
      {ct([](json& m) { m.erase("fresnel"); }), "maps[0].material.fresnel: required"},
      {ct([](json& m) {
         m["fresnel"] = {{"ior", 1.5}, {"f0", 0.04}};
       }),
       "maps[0].material.fresnel: give exactly one of"},
      {ct([](json& m) { m["fresnel"] = json::object(); }), "maps[0].material.fresnel: give exactly one of"},
      {ct([](json& m) {
         m["fresnel"] = {{"ior", 0}};
       }),
       "maps[0].material.fresnel.ior: must be in [0.001, 1000]"},
      {ct([](json& m) {
         m["fresnel"] = {{"f0", {0.5, 1.2, 0.5}}};
       }),
       "maps[0].material.fresnel.f0: must be in [0, 1]"},
      {ct([](json& m) {
         m["fresnel"] = {{"f0", "copper"}};
       }),
       "maps[0].material.fresnel.f0: must be [r, g, b] or one number"},
      {ct([](json& m) {
         m["fresnel"] = {{"n", {1, 1, 1}}};
       }),
       "maps[0].material.fresnel: \"n\" and \"k\" go together"},
      {ct([](json& m) {
         m["fresnel"] = {{"n", {0, 1, 1}}, {"k", {1, 1, 1}}};
       }),
       "maps[0].material.fresnel.n: must be in [0.001, 1000]"},
      {ct([](json& m) {
         m["fresnel"] = {{"ior", 1.5}, {"eta", 2}};
       }),
       "maps[0].material.fresnel.eta: unknown key"},
      {ct([](json& m) {
         m["fresnel"] = {{"spectral", {{"wavelengths_nm", {450, 550}}, {"n", {1, 1, 1}}, {"k", {1, 1}}}}};
       }),
       "maps[0].material.fresnel.spectral.n: needs one value per wavelength (2), got 3"},
      {ct([](json& m) {
         m["fresnel"] = {{"spectral", {{"wavelengths_nm", {550, 450}}, {"f0", {1, 1}}}}};
       }),
       "maps[0].material.fresnel.spectral.wavelengths_nm[1]: wavelengths must increase strictly"},
      {ct([](json& m) {
         m["mode"] = "lighting";
         m["grazing_angle"] = 80;
       }),
       "maps[0].material.grazing_angle: only applies to \"mode\": \"reflectance\""},
      {ct([](json& m) { m["mode"] = "lighting"; }), "maps[0].lights: cook_torrance needs at least one light"},
      {mapWith(cookTorrance(), {{"lights", {{{"direction", "eye"}}}}}), "maps[0].lights: cook_torrance ignores lights"},
      {cg([](json& m) { m.erase("blend"); }), "maps[0].material.blend: required"},
      {cg([](json& m) { m["blend"] = "multiply"; }),
       "maps[0].material.blend: blend must be one of replace, modulate, add; got \"multiply\""},
      {cg([](json& m) { m["stops"] = json::array(); }), "maps[0].material.stops: must hold at least one"},
      {cg([](json& m) { m["stops"][1]["angle"] = 0; }),
       "maps[0].material.stops[1].angle: must be greater than the previous"},
      {cg([](json& m) { m["stops"][1]["angle"] = 95; }), "maps[0].material.stops[1].angle: must be <= 90, got 95"},
      {cg([](json& m) {
         m["stops"][1]["colour"] = {1, 0, 0};
       }),
       "maps[0].material.stops[1].colour: unknown key"},
      {cg([](json& m) {
         m["stops"][0]["color"] = {1, 0.9, 0.9};
       }),
       "maps[0].material.stops[0].color: the colour at the centre (angle 0) must be [1, 1, 1] for blend \"modulate\""},
      {cg([](json& m) { m["blend"] = "add"; }),
       "maps[0].material.stops[0].color: the colour at the centre (angle 0) must be [0, 0, 0] for blend \"add\""},
      {cg([](json& m) { m["blur"] = -1; }), "maps[0].material.blur: must be >= 0"},
      {cg([](json& m) { m["twist"] = 120; }), "maps[0].material.twist: must be <= 90"},
      {mapWith({{"model", "gooch"}, {"blur", -2}}), "maps[0].material.blur: must be >= 0"},
      {mapWith({{"model", "gooch"}, {"light_direction", {0, 0, 0}}}),
       "maps[0].material.light_direction: must be a non-zero vector"},
      {mapWith({{"model", "gooch"}, {"cool", "blue"}}), "maps[0].material.cool: must be [r, g, b] or one number"},
      {mapWith({{"model", "silhouette"}}), "maps[0].material.width: required"},
      {mapWith({{"model", "silhouette"}, {"width", 0}}), "maps[0].material.width: must be > 0"},
      {mapWith({{"model", "hatching"}, {"spacing", 0}}), "maps[0].material.spacing: must be > 0"},
      {mapWith({{"model", "hatching"}, {"strokes", 3}}), "maps[0].material.strokes: unknown key"},
      {mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}, {"combine", "blend"}}),
       "maps[0].material.combine: combine must be one of add, mix; got \"blend\""},
      // Map-level keys of these models.
      {mapWith(cookTorrance(), {{"mips", true}}), "maps[0].mips: only the silhouette model defines its own mip levels"},
      {mapWith({{"model", "silhouette"}, {"width", 10}}, {{"mips", "yes"}}), "maps[0].mips: must be true or false"},
      {mapWith({{"model", "silhouette"}, {"width", 10}},
               {{"mips", true}, {"parameterization", "paraboloid"}, {"view", {0, 0, 1}}}),
       "maps[0].mips: silhouette mip levels are defined for sphere maps only"},
      {mapWith(cookTorrance(), {{"fresnel_table_output", "f.exr"}}),
       "maps[0].fresnel_table_output: only the fresnel model has a 1-D table"},
      {mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}}, {{"fresnel_table_output", "f.jpg"}}),
       "maps[0].fresnel_table_output: f.jpg: unsupported image extension"},
      {mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}}, {{"fresnel_table_output", "a.exr"}}),
       "maps[0].fresnel_table_output: same file as output"},
      // "profile_output", the key's former name, is still read, and errors name it as written.
      {mapWith(cookTorrance(), {{"profile_output", "f.exr"}}), "maps[0].profile_output: only the fresnel model"},
      {mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}},
               {{"profile_output", "a.exr"}, {"fresnel_table_output", "b.exr"}}),
       "maps[0].profile_output: the former name of \"fresnel_table_output\""},
  };
  for (const auto& c : cases) {
    const std::string error = errorFor(c.map);
    EXPECT_NE(error.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << error;
    EXPECT_EQ(error.rfind("spec.json: ", 0), 0u) << error;
  }
}

TEST(MaterialSpecs, ViewDependentModelsInAParaboloidMapNeedAView) {
  // A colorgram's colour is a function of the angle between view and normal: a map indexed by the
  // reflected direction alone cannot hold it unless the spec fixes the view.
  const std::string error = errorFor(mapWith(colorgram(), {{"parameterization", "paraboloid"}}));
  for (const char* part :
       {"maps[0]: colorgram depends on the view direction", "paraboloid map is indexed by reflected direction only",
        "fix the view with \"view\": [x, y, z]", "or use a sphere map"}) {
    EXPECT_NE(error.find(part), std::string::npos) << part << " in: " << error;
  }
  EXPECT_NO_THROW(parse(mapWith(colorgram(), {{"parameterization", "paraboloid"}, {"view", {0, 0, 1}}})));
  for (const char* model : {"gooch", "hatching"}) {
    EXPECT_NE(
        errorFor(mapWith({{"model", model}}, {{"parameterization", "cube"}})).find("depends on the view direction"),
        std::string::npos)
        << model;
  }
  EXPECT_NE(
      errorFor(mapWith(cookTorrance(), {{"parameterization", "latlong"}})).find("cook_torrance depends on the view"),
      std::string::npos);
}

TEST(MaterialSpecs, NarrowHighlightsAreRejectedUnlessSampledFinely) {
  // Lighting mode with a delta-like lobe: the spec is told its resolution is too low.
  json m = cookTorrance();
  m["mode"] = "lighting";
  m["roughness"] = 0.001;
  const json lights = {{{"direction", "eye"}}};
  const std::string error = errorFor(mapWith(m, {{"lights", lights}, {"resolution", 256}, {"samples_per_texel", 16}}));
  for (const char* part : {"maps[0].material.roughness: 0.001 makes the highlight of light 0 about", "would alias",
                           "Raise \"resolution\" to at least", "\"mode\": \"reflectance\""}) {
    EXPECT_NE(error.find(part), std::string::npos) << part << " in: " << error;
  }
  // The same lobe at the eye is 2 sin(atan m) N / 2 = m N texels across (disc radius = sin of the
  // normal's angle): m = 0.01 at N = 256 is 2.56 texels, 10 samples with 16 per texel: accepted.
  m["roughness"] = 0.01;
  EXPECT_NO_THROW(parse(mapWith(m, {{"lights", lights}, {"resolution", 256}, {"samples_per_texel", 16}})));
  // ... and at N = 32 with 1 sample per texel: 32 sin(atan 0.01) = 0.319984 samples across,
  // rejected; the suggested resolution ceil(32 x 2 / 0.319984) = 201 is accepted.
  EXPECT_NE(
      errorFor(mapWith(m, {{"lights", lights}, {"resolution", 32}, {"samples_per_texel", 1}})).find("at least 201"),
      std::string::npos);
  EXPECT_NO_THROW(parse(mapWith(m, {{"lights", lights}, {"resolution", 201}, {"samples_per_texel", 1}})));
  EXPECT_THROW(parse(mapWith(m, {{"lights", lights}, {"resolution", 199}, {"samples_per_texel", 1}})), Error);
  // Reflectance mode has no lobe, so any roughness is fine.
  json r = cookTorrance();
  r["roughness"] = 1e-4;
  EXPECT_NO_THROW(parse(mapWith(r)));
}

TEST(MaterialSpecs, ExtraOutputsParse) {
  const auto fresnel = parse(mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}, {"combine", "mix"}},
                                     {{"fresnel_table_output", "sub/f_1d.exr"}}));
  ASSERT_TRUE(fresnel.maps[0].materialMap()->fresnelTableOutput);
  EXPECT_EQ(*fresnel.maps[0].materialMap()->fresnelTableOutput, std::filesystem::path("sub/f_1d.exr"));
  // The former key name reads the same.
  const auto former =
      parse(mapWith({{"model", "fresnel"}, {"fresnel", {{"ior", 1.5}}}}, {{"profile_output", "old.exr"}}));
  ASSERT_TRUE(former.maps[0].materialMap()->fresnelTableOutput);
  EXPECT_EQ(*former.maps[0].materialMap()->fresnelTableOutput, std::filesystem::path("old.exr"));
  const auto silhouette = parse(mapWith({{"model", "silhouette"}, {"width", 10}}, {{"mips", true}}));
  EXPECT_TRUE(silhouette.maps[0].materialMap()->mips);
  EXPECT_FALSE(parse(mapWith({{"model", "silhouette"}, {"width", 10}})).maps[0].materialMap()->mips);
}

}  // namespace
}  // namespace brdfbake
