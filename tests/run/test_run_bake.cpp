// Baking specs and reading the maps back through the library (runSpec, sampleOutput,
// describeOutput, convertOutput, makePreview, chartInterpolation): values against the analytic
// lobes, the report's sizes and timings, auto's choice against a brute-force error, profiles
// against the formula, a preview's pixels against the lookup at the analytic reflection, the
// interpolation experiments against sums written here. Moved from tests/cli/test_cli.cpp, which
// keeps the tool's own part (exit statuses, flags, help, an end-to-end smoke test).
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/convert_output.hpp>
#include <brdfbake/run/interpolation_chart.hpp>
#include <brdfbake/run/preview_job.hpp>

#include <chrono>
#include <fstream>
#include <random>

#include "run_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::infoOf;
using test::sampleAt;

const std::string kPhongEye = test::sourcePath("data_samples/specs/phong_eye.json");

TEST(BakeJob, BakeAndSampleMatchTheAnalyticLobes) {
  test::TempDir dir;
  test::bakeSpec(kPhongEye, dir.path());
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  const Vec3 light = Vec3(1, 1, 1).normalized();
  for (int i = 0; i < 40; ++i) {
    const Vec3 r = Vec3(g(rng), g(rng), g(rng)).normalized();
    if (std::acos(-r.z()) > radians(10)) {
      EXPECT_NEAR(sampleAt(dir / "phong_eye.exr", r)[0], std::pow(std::max(0.0, r.z()), 50), 0.01);
    }
    EXPECT_NEAR(sampleAt(dir / "phong_paraboloid.exr", r)[0], std::pow(std::max(0.0, r.dot(light)), 50), 0.01);
  }
}

// A map without "output" in a spec run with inMemory: the map comes back in MapResult::made, nothing is
// written, and its texels hold the analytic lobe; its writer writes it later. Without inMemory (the
// tool's bake) the output stays required.
TEST(BakeJob, AMapWithoutOutputIsMadeInMemory) {
  test::TempDir dir;
  SpecRunOptions options;
  options.document = nlohmann::json::parse(R"({"maps": [{"parameterization": "paraboloid", "resolution": 128,
      "material": {"model": "phong", "exponent": 50}, "lights": [{"direction": [1, 1, 1]}]}]})");
  options.outDir = dir.path();
  options.inMemory = true;
  const SpecRunResult result = runSpec(options);
  ASSERT_EQ(result.maps.size(), 1u);
  const MapResult& map = result.maps[0];
  ASSERT_TRUE(map.made) << result.briefReport();
  EXPECT_TRUE(result.files.empty());
  EXPECT_TRUE(fs::is_empty(dir.path()));
  EXPECT_EQ(map.entry["status"], "in_memory");
  EXPECT_EQ(map.lines.at(0).rfind("made maps[0] in memory (paraboloid 256x128", 0), 0u) << map.lines.at(0);
  ASSERT_EQ(map.made->levels.size(), 1u);
  const auto paraboloid = makeParameterization(ParameterizationKind::Paraboloid, 128);
  const Vec3 light = Vec3(1, 1, 1).normalized();
  for (const Vec3& r : {Vec3(0, 0, 1), light, Vec3(0.2, -0.1, 1).normalized(), Vec3(1, 1, 0.8).normalized()}) {
    const Rgba v = sampleBilinear(map.made->levels[0], *paraboloid, r);
    EXPECT_NEAR(v[0], std::pow(std::max(0.0, r.dot(light)), 50), 0.01) << r.transpose();
  }
  const MapWriteReport written = map.made->write({.files = {dir / "later.exr"}});
  EXPECT_EQ(written.files.at(0), dir / "later.exr");
  EXPECT_NEAR(sampleAt(dir / "later.exr", light)[0], 1.0, 0.01);

  options.inMemory = false;
  EXPECT_NE(test::errorOf([&] { runSpec(options); }).find("maps[0].output"), std::string::npos);
}

TEST(BakeJob, TheReportGivesSizesFilesAndSecondsPerMap) {
  // phong_eye.json: a 256 sphere map (256 x 256 texels) and a 256 paraboloid map (two discs side
  // by side, 512 x 256).
  test::TempDir dir;
  const auto start = std::chrono::steady_clock::now();
  const auto report = test::bakeSpec(kPhongEye, dir.path());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(report["maps"].size(), 2u);
  const struct {
    const char *file, *parameterization;
    int width, height;
  } expected[2] = {{"phong_eye.exr", "sphere", 256, 256}, {"phong_paraboloid.exr", "paraboloid", 512, 256}};
  double total = 0.0;
  for (int i = 0; i < 2; ++i) {
    const auto& map = report["maps"][i];
    EXPECT_EQ(map["status"], "written");
    EXPECT_EQ(fs::path(map["output"].get<std::string>()), dir / expected[i].file);
    EXPECT_EQ(map["parameterization"], expected[i].parameterization);
    EXPECT_EQ(map["resolution"], 256);
    EXPECT_EQ(map["width"], expected[i].width);
    EXPECT_EQ(map["height"], expected[i].height);
    // Every file listed exists and holds an image of the reported size.
    ASSERT_EQ(map["files"].size(), 1u) << map.dump();
    const Image image = readImage(map["files"][0].get<std::string>());
    EXPECT_EQ(image.width(), expected[i].width);
    EXPECT_EQ(image.height(), expected[i].height);
    const double bake = map["bake_seconds"].get<double>(), write = map["write_seconds"].get<double>();
    EXPECT_GT(bake, 0.0);
    EXPECT_GT(write, 0.0);
    total += bake + write;
  }
  // The times are spent within the call: together no more than the wall time it took.
  EXPECT_LT(total, wall) << "bake + write " << total << " s, call " << wall << " s";
  // Info reports the spec; a conversion resamples the paraboloid map into a cube map that still
  // holds the lobe.
  const auto info = infoOf(dir / "phong_paraboloid.exr");
  EXPECT_EQ(info["parameterization"], "paraboloid");
  EXPECT_EQ(info["width"], 512);
  EXPECT_EQ(info["metadata"]["spec"]["material"]["exponent"], 50);
  ConvertOptions convert;
  convert.source.path = dir / "phong_paraboloid.exr";
  convert.to = ParameterizationKind::Cube;
  convert.resolution = 128;
  convert.outputs.files = {dir / "cube.exr"};
  convertOutput(convert);
  const Vec3 light = Vec3(1, 1, 1).normalized();
  for (const Vec3& d : {light, Vec3(1, 1, 0.5).normalized(), Vec3(0, 0, -1)}) {
    EXPECT_NEAR(sampleAt(dir / "cube.exr", d)[0], std::pow(std::max(0.0, d.dot(light)), 50), 0.03) << d.transpose();
  }
  // Refuses to overwrite its input.
  convert.source.path = dir / "cube.exr";
  convert.to = ParameterizationKind::Sphere;
  EXPECT_THROW(convertOutput(convert), Error);
}

TEST(BakeJob, APreviewShowsTheMapAtTheAnalyticReflectionOnEveryObject) {
  // The preview of phong_eye's sphere map as HDR values (.exr): on the sphere, pixel (x, y) shows
  // the lobe at the reflection of the analytic normal, max(0, 2 n_z^2 - 1)^50 (see
  // Preview.PerPixelLookupMatchesTheReflectionOfTheSphereNormal); the torus and the teapot cover
  // the image's centre or not as their shapes say (the torus has a hole there), and their pixels
  // are values of the map (within its range [0, 1]); the background is alpha 0.
  test::TempDir dir;
  test::bakeSpec(kPhongEye, dir.path());
  PreviewJobOptions options;
  options.source.path = dir / "phong_eye.exr";
  options.preview.resolution = 64;
  options.preview.segments = 64;
  options.output = dir / "sphere.exr";
  makePreview(options);
  const Image sphere = readImage(dir / "sphere.exr");
  ASSERT_EQ(sphere.width(), 64);
  int checked = 0;
  for (int y = 0; y < 64; y += 3)
    for (int x = 0; x < 64; x += 3) {
      const double sx = ((x + 0.5) / 32 - 1) * 1.08, sy = (1 - (y + 0.5) / 32) * 1.08, rho2 = sx * sx + sy * sy;
      if (rho2 > 0.8) continue;
      EXPECT_NEAR(sphere.at(x, y)[0], std::pow(std::max(0.0, 2 * (1 - rho2) - 1), 50), 0.03) << x << " " << y;
      ++checked;
    }
  EXPECT_GT(checked, 200);
  EXPECT_EQ(sphere.at(0, 0)[3], 0.0f);
  for (auto object : {PreviewObject::Torus, PreviewObject::Teapot}) {
    options.preview.object = object;
    options.preview.perVertex = object == PreviewObject::Torus;
    options.output = dir / (std::string(toString(object)) + ".exr");
    makePreview(options);
    const Image image = readImage(options.output);
    int covered = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x)
        if (image.at(x, y)[3] > 0) {
          ++covered;
          EXPECT_GE(image.at(x, y)[0], -1e-6f);
          EXPECT_LE(image.at(x, y)[0], 1.0f + 1e-3f);
        }
    EXPECT_GT(covered, 64 * 64 / 8) << toString(object);
    // The torus (radii 0.65, 0.35, tilted 60 degrees) leaves its hole at the centre uncovered.
    if (object == PreviewObject::Torus) {
      EXPECT_EQ(image.at(32, 32)[3], 0.0f);
    }
  }
  // A sphere map is looked up only from the view it was made for (eye space).
  options.preview.object = PreviewObject::Sphere;
  options.preview.view = Vec3(1, 0, 0);
  options.output = dir / "x.png";
  EXPECT_NE(test::errorOf([&] { makePreview(options); }).find("eye space"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST(BakeJob, AutoPicksAConfigurationAndRecordsIt) {
  test::TempDir dir;
  std::ofstream(dir / "a.json") << R"({"maps": [{"output": "a.exr", "parameterization": "auto", "resolution": "auto",
      "samples_per_texel": "auto", "max_error": 0.005, "view": "free",
      "material": {"model": "phong", "exponent": 40}, "lights": [{"direction": [1, 1, 1]}, {"direction": [-1, 0, 1]}]}]})";
  const auto report = test::bakeSpec(dir / "a.json")["maps"][0];
  EXPECT_NE(report["parameterization"], "sphere");   // a free view rules out sphere maps
  EXPECT_NE(report["parameterization"], "profile");  // two lobes about two axes: no symmetry
  const auto info = infoOf(dir / "a.exr");
  EXPECT_EQ(info["metadata"]["spec"]["auto"]["chosen"], report["auto"]["chosen"]);
  // The map as a renderer reads it (bilinear lookups) against the two Phong lobes typed out,
  // v = max(0, r.l1)^40 + max(0, r.l2)^40 (white lights and specular, no diffuse), over directions
  // uniform on the sphere: a Fibonacci lattice of 200000 points (z uniform in [-1, 1], azimuth
  // advancing by the golden angle). The value-weighted RMS, sqrt(sum v e^2 / sum v) / peak
  // (docs/accuracy.md), is within the bound asked for and close to the error the report gives;
  // the uniform RMS is far below it (the lobes cover a small part of the sphere).
  const MapFile map = readMap(dir / "a.exr");
  EXPECT_EQ(std::string(toString(map.info.parameterization)), report["parameterization"].get<std::string>());
  const Vec3 l1 = Vec3(1, 1, 1).normalized(), l2 = Vec3(-1, 0, 1).normalized();
  const int count = 200000;
  double sum = 0.0, weightedSum = 0.0, weight = 0.0, peak = 0.0;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count, phi = i * kPi * (3.0 - std::sqrt(5.0)), s = std::sqrt(1.0 - z * z);
    const Vec3 r(s * std::cos(phi), s * std::sin(phi), z);
    const double exact = std::pow(std::max(0.0, r.dot(l1)), 40) + std::pow(std::max(0.0, r.dot(l2)), 40);
    const Rgba looked = sampleBilinear(map.image, *map.parameterization, r);
    double squared = 0.0;
    for (int c = 0; c < 3; ++c) squared += (looked[c] - exact) * (looked[c] - exact) / 3.0;
    sum += squared;
    weightedSum += exact * squared;
    weight += exact;
    peak = std::max(peak, exact);
  }
  const double rms = std::sqrt(sum / count) / peak, weighted = std::sqrt(weightedSum / weight) / peak;
  const double reported = report["auto"]["measured_error"].get<double>();
  EXPECT_LT(weighted, 0.005) << "reported " << reported << " for " << report["auto"]["chosen"].dump();
  EXPECT_NEAR(weighted, reported, 0.05 * reported);
  EXPECT_LT(rms, 0.3 * weighted);
}

// A map radially symmetric about one axis needs only its 1-D profile: auto picks one, and
// "parameterization": "profile" asks for one; the profile's lookups match the exact model.
TEST(BakeJob, RadiallySymmetricMapsAreBakedAsProfiles) {
  test::TempDir dir;
  const auto maps = test::bakeSpec(test::sourcePath("data_samples/specs/profile.json"), dir.path())["maps"];
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0]["parameterization"], "profile");
  EXPECT_LE(maps[0]["auto"]["measured_error"].get<double>(), 0.002);
  EXPECT_GT(maps[0]["auto"]["next_cheaper"]["error"].get<double>(), 0.002);
  EXPECT_EQ(maps[0]["height"], 1);
  EXPECT_EQ(maps[1]["parameterization"], "profile");
  EXPECT_EQ(maps[1]["width"], 256);
  const auto info = infoOf(dir / "phong_eye_profile.exr");
  EXPECT_EQ(info["parameterization"], "profile");
  EXPECT_EQ(info["metadata"]["axis"], nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(info["metadata"]["spec"]["material"]["exponent"], 50);
  // Texel i holds Phong's lobe about the view at u = (i + 0.5) / 256: cos = 1 - 2 u^2.
  const Image profile = readImage(dir / "phong_eye_profile.exr");
  for (int i = 0; i < 256; i += 5) {
    const double u = (i + 0.5) / 256.0;
    EXPECT_NEAR(profile.at(i, 0)[0], std::pow(std::max(0.0, 1.0 - 2.0 * u * u), 50.0), 0.01) << i;
  }
  // A profile is looked up as a renderer does: at u = |r - axis| / 2.
  const Vec3 r = Vec3(0.1, 0.2, 1.0).normalized();
  EXPECT_NEAR(sampleAt(dir / "phong_eye_profile.exr", r)[0], std::pow(r.z(), 50.0), 0.01);
  // Asking for a profile of a map that is not symmetric names the JSON path and writes nothing.
  std::ofstream(dir / "bad.json") << R"({"maps": [{"output": "g.exr", "parameterization": "profile",
      "material": {"model": "phong", "exponent": 20}, "lights": [{"direction": [1, 0, 1]}, {"direction": "eye"}]}]})";
  SpecRunOptions bad;
  bad.spec = dir / "bad.json";
  EXPECT_NE(
      test::errorOf([&] { runSpec(bad); }).find("maps[0].parameterization: a profile needs a map radially symmetric"),
      std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "g.exr"));
}

TEST(InterpolationJob, ChartsBothSchemesAndTheLineExperiment) {
  test::TempDir dir;
  InterpolationOptions options;
  options.sizesDegrees = {2};
  options.placesDegrees = {0, 45, 80};
  options.csv = dir / "i.csv";
  const InterpolationResult result = chartInterpolation(options);
  EXPECT_EQ(test::filesIn(dir.path()), std::vector<std::string>{"i.csv"});  // only what was asked for
  const auto report = result.toJson();
  EXPECT_EQ(report["sweep"].size(), 3u);
  // Zimmons 1999's line, by hand: viewer e = (-8.3, 1, 0) over the plane y = 0 (normal +y), one
  // segment from x = -10 to 10. In the x-y plane the reflected view at x is r(x) = (x - e_x,
  // e_y) / |.|; the lookup interpolates r(-10) and r(10) linearly. The largest angle between the
  // two over the 4001 points x_i = -10 + 20 i / 4000:
  auto r = [](double x) { return Vec2(x + 8.3, 1.0).normalized(); };
  double worst = 0.0, worstAt = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double x = -10.0 + 20.0 * i / 4000.0, t = (x + 10.0) / 20.0;
    const Vec2 lerp = (1.0 - t) * r(-10.0) + t * r(10.0), exact = r(x);
    const double angle = degrees(std::atan2(std::abs(lerp.x() * exact.y() - lerp.y() * exact.x()), lerp.dot(exact)));
    if (angle > worst) worst = angle, worstAt = x;
  }
  EXPECT_GT(worst, 10.0);  // Zimmons 1999's point: one polygon is far too coarse here
  EXPECT_NEAR(report["line"]["max_error_degrees"].get<double>(), worst, 1e-9);
  EXPECT_NEAR(report["line"]["at_x"].get<double>(), worstAt, 1e-9);
  // One sweep point by brute force: triangles of normals 2 degrees apart centred on the view axis
  // (place 0). Per-vertex reflected vectors r_v = 2 n_z n - z, interpolated, against the reflected
  // vector of the normalised interpolated normal; sphere-map coordinates (s, t) = r_xy / (2
  // sqrt(2 (1 + r_z))) + 1/2 interpolated and turned back into the direction whose normal has
  // xy = 2 (s, t) - 1. Worst over 24 x 24 barycentric steps and the 12 orientations (10 degree
  // steps, the triangle's symmetry repeats every 120) the sweep takes.
  auto angleBetween = [](const Vec3& a, const Vec3& b) { return degrees(std::atan2(a.cross(b).norm(), a.dot(b))); };
  auto reflectView = [](const Vec3& n) { return Vec3(2.0 * n.z() * n - Vec3::UnitZ()); };
  double worstSphere = 0.0, worstVector = 0.0;
  const double radius = radians(2.0) / std::sqrt(3.0);
  for (int k = 0; k < 12; ++k) {
    Vec3 normals[3], reflected[3];
    Vec2 st[3];
    for (int v = 0; v < 3; ++v) {
      const double phi = kTwoPi * (k / 36.0 + v / 3.0);
      // Centre +z; u = +y, w = centre x u = -x.
      normals[v] = Vec3(-std::sin(radius) * std::sin(phi), std::sin(radius) * std::cos(phi), std::cos(radius));
      reflected[v] = reflectView(normals[v]);
      st[v] = reflected[v].head<2>() / (2.0 * std::sqrt(2.0 * (1.0 + reflected[v].z()))) + Vec2(0.5, 0.5);
    }
    for (int i = 0; i <= 24; ++i)
      for (int j = 0; i + j <= 24; ++j) {
        const double a = i / 24.0, b = j / 24.0, c = 1.0 - a - b;
        const Vec3 exact = reflectView((a * normals[0] + b * normals[1] + c * normals[2]).normalized());
        worstVector =
            std::max(worstVector, angleBetween(a * reflected[0] + b * reflected[1] + c * reflected[2], exact));
        const Vec2 xy = 2.0 * (a * st[0] + b * st[1] + c * st[2]) - Vec2(1.0, 1.0);
        const Vec3 n(xy.x(), xy.y(), std::sqrt(std::max(0.0, 1.0 - xy.squaredNorm())));
        worstSphere = std::max(worstSphere, angleBetween(reflectView(n), exact));
      }
  }
  const auto& first = report["sweep"][0];
  EXPECT_EQ(first["size_degrees"], 2.0);
  EXPECT_EQ(first["place_degrees"], 0.0);
  EXPECT_GT(worstSphere, 0.0);
  EXPECT_GT(worstVector, 0.0);
  EXPECT_NEAR(first["sphere_map_error_degrees"].get<double>(), worstSphere, 1e-6 * worstSphere + 1e-9);
  EXPECT_NEAR(first["reflected_vector_error_degrees"].get<double>(), worstVector, 1e-6 * worstVector + 1e-9);
}

}  // namespace
}  // namespace brdfbake
