// Baking the material models of docs/materials.md: sample specs bake with finite values at every
// texel, maps hold the documented quantity texel by texel, narrow lobes integrate correctly (or
// are rejected), and the silhouette mip chain keeps its ring width in texels.
#include <gtest/gtest.h>
#include <brdfbake/bake/baked_mips.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/sphere_map.hpp>
#include <brdfbake/spec/spec.hpp>

#include "brdf_references.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
using test::eq13;

BakeOptions options(int samples) {
  BakeOptions o;
  o.samplesPerTexel = samples;
  return o;
}

Image bakeMaterial(std::shared_ptr<const Material> material, std::vector<DirectionalLight> lights,
                   ParameterizationKind kind, int resolution, int samples, const Vec3& view = Vec3::UnitZ()) {
  const auto map = makeParameterization(kind, resolution);
  const MaterialMapFunction function(std::move(material), std::move(lights), view);
  return bake(*map, function, options(samples));
}

// Every texel's RGBA is finite and its colour >= 0.
void expectFinite(const Image& image, const std::string& what) {
  int bad = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgba v = image.at(x, y);
      if (!allFinite(v) || (v.head<3>() < 0.0).any()) {
        if (++bad <= 3) ADD_FAILURE() << what << ": texel (" << x << ", " << y << ") = " << v.transpose();
      }
    }
  }
  EXPECT_EQ(bad, 0) << what;
}

// The normal a sphere-map texel centre stands for (disc coordinates, eye space), nullopt outside.
std::optional<Vec3> texelNormal(int x, int y, int n) {
  const double sx = 2.0 * (x + 0.5) / n - 1.0, sy = 1.0 - 2.0 * (y + 0.5) / n;
  const double rho2 = sx * sx + sy * sy;
  if (rho2 >= 1.0) return std::nullopt;
  return Vec3(sx, sy, std::sqrt(1.0 - rho2));
}

CookTorranceParams ctParams(CookTorranceMode mode, double roughness, FresnelTerm f) {
  CookTorranceParams p;
  p.mode = mode;
  p.roughness = roughness;
  p.fresnel = std::move(f);
  return p;
}

TEST(MaterialsBake, SampleSpecsBakeFiniteEverywhere) {
  for (const char* name : {"copper", "plastic", "colorgram", "gooch", "silhouette", "hatching", "fresnel"}) {
    const BakeSpec spec = loadBakeSpec(test::sourcePath(std::string("data_samples/specs/") + name + ".json"));
    test::TempDir dir;
    for (MapSpec map : spec.maps) {
      map.resolution = std::min(map.resolution, 128);
      map.output = dir / map.output.filename().string();
      const auto parameterization = makeParameterization(map.parameterization, map.resolution);
      const Image image = bake(*parameterization, *map.makeFunction(), options(map.samplesPerTexel));
      expectFinite(image, std::string(name) + " " + map.jsonPath);
      const MapWriteReport extras = writeMapExtras(map, options(map.samplesPerTexel));
      for (const auto& file : extras.files) expectFinite(readImage(file), file.string());
    }
  }
}

TEST(MaterialsBake, ReflectanceMapIsFOverCosSquaredUpToTheGrazingPolicy) {
  auto p = ctParams(CookTorranceMode::Reflectance, 0.3, FresnelTerm::dielectric(Rgb::Constant(1.5)));
  const auto material = std::make_shared<CookTorranceMaterial>(p);
  const int n = 96;
  const Image image = bakeMaterial(material, {}, ParameterizationKind::Sphere, n, 1);  // 1 sample: the texel centre
  const double peak = 1.0 / (kPi * 0.09), cmin = std::cos(radians(80.0));
  int inside = 0, held = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const auto normal = texelNormal(x, y, n);
      const double c = normal ? normal->z() : 0.0;  // outside the disc: the rim direction -z
      const double expected = peak * eq13(c, 1.5) / (4.0 * std::pow(std::max(c, cmin), 2));
      EXPECT_NEAR(image.at(x, y)[1], expected, 2e-6 * expected) << x << " " << y;
      inside += normal.has_value();
      held += normal && c < cmin;
    }
  }
  EXPECT_GT(held, 0);  // the map reaches the grazing band
  EXPECT_GT(inside, 7000);
  // Finite at the rim with the stated limit: F = 1, scale 1 / (4 c_min^2).
  EXPECT_NEAR(image.at(0, 0)[0], peak / (4 * cmin * cmin), 1e-5 * peak / (4 * cmin * cmin));
}

TEST(MaterialsBake, CopperColourShiftsTowardsWhiteAtGrazing) {
  const BakeSpec spec = loadBakeSpec(test::sourcePath("data_samples/specs/copper.json"));
  const MapSpec& map = spec.maps[0];
  ASSERT_EQ(map.output.filename(), "copper_reflectance.exr");
  const auto sphere = makeParameterization(map.parameterization, 128);
  const Image image = bake(*sphere, *map.makeFunction(), options(16));
  // Along the +x radius: green / red starts at copper's F0 ratio and rises towards 1 (white) at the
  // rim. (Between 0 and ~40 degrees a conductor's ratio dips by ~1e-4, so the rise is checked from 45.)
  auto ratioAt = [&](double deg) {
    const double t = radians(deg);  // normal angle; the reflected direction is at 2t
    const Rgba v = sampleBilinear(image, *sphere, Vec3(std::sin(2 * t), 0.0, std::cos(2 * t)));
    return v[1] / v[0];
  };
  EXPECT_NEAR(ratioAt(0.0), 0.6194 / 0.9433, 2e-3);
  double previous = ratioAt(45.0);
  for (double deg : {60.0, 75.0, 85.0}) {  // 85: the outermost texel of a 128 map
    EXPECT_GT(ratioAt(deg), previous) << deg;
    previous = ratioAt(deg);
  }
  EXPECT_GT(previous, ratioAt(0.0) + 0.15);
  EXPECT_NEAR(image.at(0, 0)[1] / image.at(0, 0)[0], 1.0, 1e-6);  // beyond the rim: F = 1, white
}

TEST(MaterialsBake, FresnelMapAndProfileHoldFOfNDotV) {
  test::TempDir dir;
  const nlohmann::json doc = {
      {"maps",
       {{{"output", "f.exr"},
         {"parameterization", "sphere"},
         {"resolution", 48},
         {"samples_per_texel", 1},
         {"fresnel_table_output", "f_1d.exr"},
         {"material", {{"model", "fresnel"}, {"fresnel", {{"ior", {1.5, 1.33, 2.4}}}}, {"combine", "mix"}}}}}}};
  const BakeSpec spec = parseBakeSpec(doc, dir.path());
  const MapSpec& map = spec.maps[0];
  const auto sphere = makeParameterization(ParameterizationKind::Sphere, 48);
  const Image image = bake(*sphere, *map.makeFunction(), options(1));
  const Rgb eta(1.5, 1.33, 2.4);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 48; ++x) {
      const auto normal = texelNormal(x, y, 48);
      const double c = normal ? normal->z() : 0.0;
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(image.at(x, y)[ch], eq13(c, eta[ch]), 1e-6) << x << " " << y;
    }
  }
  const MapWriteReport written = writeMapExtras(map, options(1));
  ASSERT_EQ(written.files.size(), 1u);
  EXPECT_EQ(written.files[0], dir / "f_1d.exr");
  const Image profile = readImage(written.files[0]);
  ASSERT_EQ(profile.width(), 48);
  ASSERT_EQ(profile.height(), 1);
  for (int i = 0; i < 48; ++i) {
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(profile.at(i, 0)[ch], eq13((i + 0.5) / 48, eta[ch]), 1e-6) << i;
  }
}

// Integral over the sphere of reflected directions of the lighting-mode map function for a light
// at the eye, computed in normal space (r = reflect(v, n), dw_r = 4 (n.v) dw_n) on a fine polar grid.
double exactIntegral(const CookTorranceMaterial& m) {
  const Vec3 v = Vec3::UnitZ();
  const int nt = 200000;
  const double dt = (kPi / 2) / nt;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * dt;
    const Vec3 n(std::sin(t), 0.0, std::cos(t));  // radially symmetric about v: one azimuth suffices
    const ShadingGeometry g{n, v, reflect(v, n)};
    sum += m.shade(g, v)[0] * 4 * std::cos(t) * std::sin(t);
  }
  return sum * dt * kTwoPi;
}

double mapIntegral(const Image& image) {
  double sum = 0.0;  // equal-area sphere map: 16 / N^2 sr per texel of the disc (and outside = rim)
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) sum += image.at(x, y)[0] * image.at(x, y)[3];
  }
  return sum * 16.0 / (static_cast<double>(image.width()) * image.width());
}

TEST(MaterialsBake, NarrowLobesIntegrateOrAreRejected) {
  // m = 0.01 at N = 64, 16 samples: the lobe is 0.64 texels, 2.56 samples across -- the spec
  // accepts it, and the footprint integration gets its integral right.
  const int n = 64;
  const auto accepted = std::make_shared<CookTorranceMaterial>(
      ctParams(CookTorranceMode::Lighting, 0.01, FresnelTerm::dielectric(Rgb::Constant(1.5))));
  const Image image = bakeMaterial(accepted, {{Vec3::UnitZ()}}, ParameterizationKind::Sphere, n, 16);
  expectFinite(image, "narrow lobe");
  const double exact = exactIntegral(*accepted);
  EXPECT_NEAR(mapIntegral(image), exact, 1e-4 * exact);  // measured: 4e-7
  // m = 0.001 at N = 64 with 1 sample per texel: the spec is rejected ...
  nlohmann::json mat = {
      {"model", "cook_torrance"}, {"mode", "lighting"}, {"roughness", 0.001}, {"fresnel", {{"ior", 1.5}}}};
  const nlohmann::json doc = {{"maps",
                               {{{"output", "x.exr"},
                                 {"parameterization", "sphere"},
                                 {"resolution", n},
                                 {"samples_per_texel", 1},
                                 {"material", mat},
                                 {"lights", {{{"direction", "eye"}}}}}}}};
  EXPECT_THROW(parseBakeSpec(doc, "."), Error);
  // ... because baking it anyway misses the lobe (its peak falls between the texel centres).
  const auto rejected = std::make_shared<CookTorranceMaterial>(
      ctParams(CookTorranceMode::Lighting, 0.001, FresnelTerm::dielectric(Rgb::Constant(1.5))));
  const Image aliased = bakeMaterial(rejected, {{Vec3::UnitZ()}}, ParameterizationKind::Sphere, n, 1);
  expectFinite(aliased, "aliased lobe");
  const double exactNarrow = exactIntegral(*rejected);
  EXPECT_GT(std::abs(mapIntegral(aliased) - exactNarrow), 0.5 * exactNarrow);
}

TEST(MaterialsBake, StressCasesAreFiniteAtEveryTexel) {
  struct Case {
    std::string name;
    std::shared_ptr<const Material> material;
    std::vector<DirectionalLight> lights;
  };
  const FresnelTerm glass = FresnelTerm::dielectric(Rgb::Constant(1.5));
  auto ct = [](CookTorranceMode mode, double m, FresnelTerm f,
               MicrofacetDistribution d = MicrofacetDistribution::Beckmann) {
    auto p = ctParams(mode, m, std::move(f));
    p.distribution = d;
    return std::make_shared<CookTorranceMaterial>(p);
  };
  const auto R = CookTorranceMode::Reflectance, L = CookTorranceMode::Lighting;
  const std::vector<DirectionalLight> eye{{Vec3::UnitZ()}}, below{{Vec3(0, 0, -1)}}, belowSide{{Vec3(0, -1, -0.2)}},
      grazingLight{{Vec3(1, 0, 0)}};
  const std::vector<Case> cases{
      {"reflectance m=1e-4", ct(R, 1e-4, glass), {}},
      {"reflectance m=10", ct(R, 10, glass, MicrofacetDistribution::Ggx), {}},
      {"reflectance eta<1", ct(R, 0.3, FresnelTerm::dielectric(Rgb(0.5, 0.67, 0.9))), {}},
      {"reflectance F0=0", ct(R, 0.3, FresnelTerm::fromF0(Rgb::Zero())), {}},
      {"reflectance F0=1", ct(R, 0.3, FresnelTerm::fromF0(Rgb::Ones())), {}},
      {"lighting m=10", ct(L, 10, glass), eye},
      {"lighting eta<1", ct(L, 0.3, FresnelTerm::dielectric(Rgb::Constant(0.6))), eye},
      {"lighting F0=0,1", ct(L, 0.3, FresnelTerm::fromF0(Rgb(0, 1, 0.5))), grazingLight},
      {"lighting below horizon", ct(L, 0.3, glass, MicrofacetDistribution::Ggx), below},
      {"lighting below horizon, side", ct(L, 0.3, glass), belowSide},
      {"lighting grazing light", ct(L, 0.2, glass), grazingLight},
      {"colorgram",
       std::make_shared<ColorgramMaterial>(
           ColorGradient({{0, Rgb::Ones()}, {60, Rgb(1, 0, 0)}, {90, Rgb(0, 0, 1)}}, 3.0), 30.0,
           ColorgramBlend::Modulate),
       {}},
      {"gooch", std::make_shared<GoochMaterial>(GoochParams{}), {}},
      {"silhouette", std::make_shared<SilhouetteMaterial>(5.0), {}},
      {"hatching", std::make_shared<HatchingMaterial>(HatchingParams{}), {}},
  };
  for (const auto& c : cases) {
    expectFinite(bakeMaterial(c.material, c.lights, ParameterizationKind::Sphere, 64, 4), c.name + " sphere");
    expectFinite(
        bakeMaterial(c.material, c.lights, ParameterizationKind::Paraboloid, 32, 4, Vec3(0.3, 0.2, 1).normalized()),
        c.name + " paraboloid");
  }
  // A light below the horizon of every texel's normal lights nothing: exactly 0 where N.L <= 0.
  const Image dark = bakeMaterial(ct(L, 0.3, glass), belowSide, ParameterizationKind::Sphere, 64, 1);
  int zero = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const auto normal = texelNormal(x, y, 64);
      if (normal && normal->dot(belowSide[0].direction.normalized()) <= 0.0) {
        EXPECT_EQ(dark.at(x, y).head<3>().maxCoeff(), 0.0) << x << " " << y;
        ++zero;
      }
    }
  }
  EXPECT_GT(zero, 1000);
  const Image allBelow = bakeMaterial(ct(L, 0.3, glass), below, ParameterizationKind::Sphere, 32, 4);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) EXPECT_EQ(allBelow.at(x, y).head<3>().maxCoeff(), 0.0);
  }
}

// Every texel of a 64 sphere map (view +z) whose footprint lies inside the disc averages the
// formula over its footprint, so each channel lies within the formula's range over the texel's
// square (sampled at 33 x 33 points, widened by the formula's change between two neighbouring
// points). `formula` takes the normal the disc point stands for. Returns the texels checked.
int expectTexelsWithinTheFormulaOverTheirFootprint(const Image& image, const std::function<Rgb(const Vec3&)>& formula,
                                                   const std::string& what) {
  const int n = image.width();
  int checked = 0, bad = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      bool inside = true;
      for (int corner = 0; corner < 4; ++corner) {
        const double cx = 2.0 * (x + corner % 2) / n - 1.0, cy = 1.0 - 2.0 * (y + corner / 2) / n;
        inside = inside && cx * cx + cy * cy < 1.0;
      }
      if (!inside) continue;
      Rgb lo = Rgb::Constant(1e300), hi = Rgb::Constant(-1e300), step = Rgb::Zero(), previous = Rgb::Zero();
      for (int i = 0; i <= 32; ++i) {
        for (int j = 0; j <= 32; ++j) {
          const double sx = 2.0 * (x + i / 32.0) / n - 1.0, sy = 1.0 - 2.0 * (y + j / 32.0) / n;
          const Rgb value = formula(Vec3(sx, sy, std::sqrt(1.0 - sx * sx - sy * sy)));
          lo = lo.min(value), hi = hi.max(value);
          if (j > 0) step = step.max((value - previous).abs());
          previous = value;
        }
      }
      const Rgb texel = image.at(x, y).head<3>();
      ++checked;
      if ((texel < lo - step - 1e-6).any() || (texel > hi + step + 1e-6).any()) {
        if (++bad <= 3)
          ADD_FAILURE() << what << ": texel (" << x << ", " << y << ") = " << texel.transpose() << " outside ["
                        << lo.transpose() << "] .. [" << hi.transpose() << "]";
      }
    }
  }
  EXPECT_EQ(bad, 0) << what;
  return checked;
}

TEST(MaterialsBake, ColorgramAndGoochTexelsHoldTheirFormulas) {
  // The twisted colorgram of Zimmons & Bastos 1999 section 6 (docs/materials.md): gradient(theta -
  // twist n.x), the gradient linear between its stops (white to 40 degrees, red at 60, blue from
  // 80), mirrored about 0 and held beyond the last stop.
  const std::vector<ColorStop> stops{{0, Rgb::Ones()}, {40, Rgb::Ones()}, {60, Rgb(1, 0, 0)}, {80, Rgb(0, 0, 1)}};
  auto gradient = [&](double theta) -> Rgb {
    theta = std::abs(theta);
    if (theta >= 80.0) return Rgb(0, 0, 1);
    if (theta <= 40.0) return Rgb::Ones();
    if (theta <= 60.0) return Rgb::Ones() + (Rgb(1, 0, 0) - Rgb::Ones()) * ((theta - 40.0) / 20.0);
    return Rgb(1, 0, 0) + (Rgb(0, 0, 1) - Rgb(1, 0, 0)) * ((theta - 60.0) / 20.0);
  };
  const double twist = 15.0;
  const auto colorgram =
      std::make_shared<ColorgramMaterial>(ColorGradient(stops, 0.0), twist, ColorgramBlend::Modulate);
  const Image image = bakeMaterial(colorgram, {}, ParameterizationKind::Sphere, 64, 16);
  auto colorgramAt = [&](const Vec3& n) { return gradient(degrees(std::acos(n.z())) - twist * n.x()); };
  EXPECT_GT(expectTexelsWithinTheFormulaOverTheirFootprint(image, colorgramAt, "colorgram"), 2500);
  // The twist by the formula: on the row below the centre, 40 degrees from it (x = -+0.641 at
  // texels 11 and 52), the right side reads gradient(40 - 9.6) = white, the left gradient(40 +
  // 9.6), green 0.53; above and below the centre, no shift.
  const Rgb right = image.at(52, 32).head<3>(), left = image.at(11, 32).head<3>();
  EXPECT_LT((right - Rgb::Ones()).abs().maxCoeff(), 1e-6);
  const double sx = 2.0 * 11.5 / 64 - 1.0, sy = 1.0 - 2.0 * 32.5 / 64;
  EXPECT_NEAR(left[1], colorgramAt(Vec3(sx, sy, std::sqrt(1.0 - sx * sx - sy * sy)))[1], 0.03);
  EXPECT_LT(left[1], 0.6);
  EXPECT_LT((image.at(32, 11).head<3>() - image.at(32, 52).head<3>()).abs().maxCoeff(), 1e-6);

  // Gooch's default map (blur 20 degrees, highlight 10 degrees about h): Heidrich 2000 section 4.
  const GoochParams p;
  const Vec3 l = p.lightDirection.normalized(), h = (l + Vec3::UnitZ()).normalized();
  auto phi = [&](double x) { return 0.5 * std::erfc(-x / p.blur / std::sqrt(2.0)); };
  auto goochAt = [&](const Vec3& n) -> Rgb {
    const double t = phi(degrees(std::asin(n.dot(l)))), w = phi(p.highlightSize - degrees(std::acos(n.dot(h))));
    return (1 - w) * ((1 - t) * p.cool + t * p.warm) + w * p.highlight;
  };
  const Image gooch = bakeMaterial(std::make_shared<GoochMaterial>(p), {}, ParameterizationKind::Sphere, 64, 16);
  EXPECT_GT(expectTexelsWithinTheFormulaOverTheirFootprint(gooch, goochAt, "gooch"), 2500);
}

// Ink of the ring along the row just below the centre, right half: sum of (1 - value) x coverage,
// which is the ring's radial width in texels (the row is radial to within half a texel).
double ringWidthTexels(const Image& image) {
  const int n = image.width(), y = n / 2;
  double ink = 0.0;
  for (int x = n / 2; x < n; ++x) ink += (1.0 - image.at(x, y)[0]) * image.at(x, y)[3];
  return ink;
}

TEST(MaterialsBake, SilhouetteMipChainKeepsTheRingWidthInTexels) {
  // The ring is where theta > 75 degrees: disc radius sin(theta) > cos(15 degrees), out to 1, so
  // (1 - cos 15 deg) x 128 = 4.36 texels of the 256 map's radius; every level keeps that width.
  const SilhouetteMaterial s(15.0);
  const double t0 = (1.0 - std::cos(15.0 * kPi / 180.0)) * 128.0;
  EXPECT_NEAR(s.ringTexels(256), t0, 1e-12);
  const auto chain = silhouetteMipChain(s, 256, options(16));
  ASSERT_EQ(chain.size(), 9u);
  for (std::size_t level = 0; level < chain.size(); ++level) {
    const int res = 256 >> level;
    ASSERT_EQ(chain[level].width(), res);
    expectFinite(chain[level], "mip " + std::to_string(level));
    if (res >= 16) {
      EXPECT_NEAR(ringWidthTexels(chain[level]), t0, 0.3) << "level " << level;
    }
  }
  // Level 0 is the ordinary silhouette map; a plain box-filtered chain would halve the width per level.
  const Image plain = bakeMaterial(std::make_shared<SilhouetteMaterial>(s), {}, ParameterizationKind::Sphere, 256, 16);
  EXPECT_NEAR(ringWidthTexels(plain), ringWidthTexels(chain[0]), 1e-6);
  const Image plain32 = bakeMaterial(std::make_shared<SilhouetteMaterial>(s), {}, ParameterizationKind::Sphere, 32, 16);
  EXPECT_NEAR(ringWidthTexels(plain32), t0 / 8, 0.3);
}

TEST(MaterialsBake, MipsAreWrittenBesideTheMap) {
  test::TempDir dir;
  const nlohmann::json doc = {{"maps",
                               {{{"output", "ring.exr"},
                                 {"parameterization", "sphere"},
                                 {"resolution", 32},
                                 {"samples_per_texel", 4},
                                 {"mips", true},
                                 {"material", {{"model", "silhouette"}, {"width", 20}}}}}}};
  const BakeSpec spec = parseBakeSpec(doc, dir.path());
  const MapWriteReport written = writeMapExtras(spec.maps[0], options(4));
  ASSERT_EQ(written.files.size(), 5u);  // 16, 8, 4, 2, 1
  for (int level = 1; level <= 5; ++level) {
    const auto path = dir / ("ring_mip" + std::to_string(level) + ".exr");
    EXPECT_EQ(written.files[level - 1], path);
    const MapFile file = readMap(path);
    EXPECT_EQ(file.info.resolution, 32 >> level);
    EXPECT_EQ(file.image.width(), 32 >> level);
    EXPECT_EQ(file.info.spec["mips"], true);
    // Each level written keeps level 0's ring width in texels, measured on the file:
    // (1 - cos 20 deg) x 16 = 0.965 texels, until the ring fills a level's radius (levels of 2, 1).
    if (32 >> level >= 8) {
      EXPECT_NEAR(ringWidthTexels(file.image), (1.0 - std::cos(20.0 * kPi / 180.0)) * 16.0, 0.3) << path;
    }
  }
}

}  // namespace
}  // namespace brdfbake
