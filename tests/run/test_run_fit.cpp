// Fitting tables and evaluating BRDFs through the library (fitTable, evaluateBrdf, runSpec), with
// values against the formula computed here from fit.json's numbers, a table's own rows, and the
// Phong formula. Moved from tests/cli/test_fit_cli.cpp, which keeps the flags, exit statuses and
// the tool's default output name.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/run/evaluate.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <fstream>
#include <sstream>

#include "fit_formula.hpp"
#include "run_support.hpp"

namespace brdfbake {
namespace {
using test::cornellDirection;
namespace fs = std::filesystem;
using test::fitFormula;
using test::readJsonFile;

// `brdfbake eval MODEL --wi WI --wo WO`: the values per channel.
std::vector<double> evaluate(const fs::path& model, const Vec3& wi, const Vec3& wo) {
  EvaluateOptions options;
  options.model = model;
  options.wi = wi;
  options.wo = wo;
  const EvaluateResult result = evaluateBrdf(options);
  const Eigen::VectorXd& v = *result.rows.at(0).value;
  return {v.data(), v.data() + v.size()};
}

FitTableOptions fitOf(const std::string& table, const fs::path& output) {
  FitTableOptions options;
  options.table = table;
  options.output = output;
  return options;
}

TEST(FitJob, FitsASyntheticTableAndEvalMatchesTheFormula) {
  test::TempDir dir;
  // The per-channel method (the shared one has its own tests in tests/fit/test_fit_families.cpp).
  FitTableOptions options = fitOf(test::sourcePath("data_samples/tables/synthetic_varying.astm"), dir / "fit.json");
  options.fit.method = FitMethod::PerChannel;
  const FitTableResult fitted = fitTable(options);
  EXPECT_EQ(fitted.files, std::vector<fs::path>{dir / "fit.json"});
  const auto document = readJsonFile(dir / "fit.json");
  EXPECT_EQ(document, fitted.toJson()["fit"]);  // --json holds the document written
  EXPECT_EQ(document["format"], "brdfbake.lobe_fit");
  EXPECT_EQ(document["version"], 1);
  EXPECT_EQ(document["model"]["elevation"], "varying");  // the table was made from varying lobes
  EXPECT_TRUE(document["fit"]["usable"].get<bool>());
  for (const auto& channel : document["channels"]) {
    EXPECT_EQ(channel["stats"]["termination"], "CONVERGENCE");
    EXPECT_LT(channel["stats"]["log_rmse"].get<double>(), 0.02);  // 1 % noise
  }
  for (const auto& [wi, wo] :
       std::vector<std::pair<Vec3, Vec3>>{{cornellDirection(radians(30), 0), cornellDirection(radians(30), kPi)},
                                          {cornellDirection(radians(70), 0.3), cornellDirection(radians(65), 3.5)},
                                          {cornellDirection(radians(10), 1.0), cornellDirection(radians(50), 0.2)}}) {
    EvaluateOptions eval;
    eval.model = dir / "fit.json";
    eval.wi = wi;
    eval.wo = wo;
    const auto result = evaluateBrdf(eval).toJson();
    ASSERT_EQ(result["value"].size(), 3u);
    EXPECT_EQ(result["channels"], nlohmann::json({"R", "G", "B"}));
    for (std::size_t c = 0; c < 3; ++c) {
      const double expected = fitFormula(document, c, wi, wo);
      EXPECT_NEAR(result["value"][c].get<double>(), expected, 1e-9 * std::max(1.0, expected));
    }
  }
}

TEST(FitJob, TheReportNamesASplitThatOneRowDecides) {
  FitTableResult result;
  result.file.fit.model.channels = {{"Y", 0.5, {}}};
  HeldOutReport report;
  report.kfold = {"off-mirror 5-fold", 0.0, 10, 0.1, 0.3, 0.4, 0.3, {0.2, 0.0, 0.3, 1.0}, 9.0};  // 40 %: no line
  report.elevations = {{"theta_i 30 deg", 30.0, 10, 0.2, 0.4, 0.9, 0.8, {0.5, 0.0, 0.6, 3.1}, 3.0}};
  result.file.fit.heldOut = report;
  const std::string text = result.briefReport();
  // theta_i 0.5 rad = 28.6 deg, theta_s 0.6 rad = 34.4 deg; without it 0.5 sqrt(0.1 / 0.2) = 0.35.
  EXPECT_NE(text.find("  theta_i 30 deg: one row holds 90 % of the squared error and 80 % of Lambert's (theta_i "
                      "28.6, theta_s 34.4 deg: 3.0 deg from the mirror direction); without it 0.35x\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("off-mirror 5-fold: one row"), std::string::npos) << text;
}

TEST(FitJob, EvalPairsGivesOneRowPerInputLine) {
  test::TempDir dir;
  const fs::path fitFile = test::sourcePath("data_samples/fits/synthetic_two_lobes.json");
  std::ofstream(dir / "pairs.txt") << "0.5236 0 0.5236 3.14159\n# a comment\n\n1.0 0 0.3 -1.0\n";
  EvaluateOptions options;
  options.model = fitFile;
  options.pairs = dir / "pairs.txt";
  const EvaluateResult result = evaluateBrdf(options);
  ASSERT_EQ(result.rows.size(), 4u);
  EXPECT_EQ(result.rows[1].text, "# a comment");
  EXPECT_FALSE(result.rows[1].value);
  EXPECT_FALSE(result.rows[2].value);
  const auto document = readJsonFile(fitFile);
  ASSERT_TRUE(result.rows[0].value);
  for (std::size_t c = 0; c < 3; ++c) {
    const double v = (*result.rows[0].value)[static_cast<Eigen::Index>(c)];
    EXPECT_NEAR(v, fitFormula(document, c, cornellDirection(0.5236, 0), cornellDirection(0.5236, 3.14159)),
                1e-9 * std::max(1.0, v));
  }
  EXPECT_EQ(result.rows[3].line, 4);
  // A bad line names the file and line; three numbers are not a pair.
  std::ofstream(dir / "bad.txt") << "0.5 0 0.5 3.1\n0.5 0 zero 3.1\n";
  options.pairs = dir / "bad.txt";
  EXPECT_NE(test::errorOf([&] { evaluateBrdf(options); }).find("bad.txt:2:"), std::string::npos);
  std::ofstream(dir / "three.txt") << "0.5 0 0.5\n";
  options.pairs = dir / "three.txt";
  EXPECT_NE(test::errorOf([&] { evaluateBrdf(options); }).find("three.txt:1: expected 4 numbers"), std::string::npos);
}

TEST(FitJob, EvalOfATableReturnsItsSamplesAndOfAMaterialItsBrdf) {
  test::TempDir dir;
  // A table sample: the first data row of the synthetic table.
  std::ifstream in(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm"));
  std::string line;
  while (std::getline(in, line) && line.rfind("VARS", 0) != 0) {
  }
  while (std::getline(in, line) && line.empty()) {
  }
  std::vector<double> row;
  std::stringstream fields(line);
  for (std::string f; std::getline(fields, f, ',');) row.push_back(std::stod(f));
  ASSERT_EQ(row.size(), 7u);
  const auto value = evaluate(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm"),
                              cornellDirection(row[0], row[1]), cornellDirection(row[2], row[3]));
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(value[c], row[4 + c], 1e-12 * std::max(1.0, row[4 + c]));

  // Phong as a material: shade / (n.l) = k_s max(0, r.l)^n / (n.l).
  std::ofstream(dir / "phong.json") << R"({"model": "phong", "specular": [1, 0.5, 0.25], "exponent": 20})";
  const Vec3 wi = cornellDirection(0.6, 0.0), wo = cornellDirection(0.5, kPi + 0.1);
  const double expected = std::pow(Vec3(-wo.x(), -wo.y(), wo.z()).dot(wi), 20) / wi.z();
  const auto phong = evaluate(dir / "phong.json", wi, wo);
  EXPECT_NEAR(phong[0], expected, 1e-9);
  EXPECT_NEAR(phong[2], 0.25 * expected, 1e-9);
}

TEST(FitJob, EvalNamesItsColumnsWhenThereAreMoreThanThree) {
  // The line `eval` prints to stderr once: the channel names in order, only beyond RGB.
  EvaluateResult result;
  result.channels = {"R", "G", "B"};
  EXPECT_EQ(result.columnsLine(), "");
  result.channels = {"400", "410", "420", "430"};
  EXPECT_EQ(result.columnsLine(), "columns (4 channels): 400 410 420 430\n");
}

// A fixed exponent cap bounds every lobe (recorded as fit.max_exponent); the default, auto, starts
// at 1e4 and records the cap it kept.
TEST(FitJob, AFixedExponentCapBoundsEveryLobe) {
  test::TempDir dir;
  const std::string table = test::sourcePath("data_samples/tables/synthetic_two_lobes.astm");
  FitTableOptions capped = fitOf(table, dir / "capped.json");
  capped.fit.lobes = 2;
  capped.fit.kind = LobeKindChoice::Mirror;
  capped.fit.maxExponent = 40;
  capped.fit.chooseMaxExponent = false;
  fitTable(capped);
  const auto document = readJsonFile(dir / "capped.json");
  EXPECT_DOUBLE_EQ(document["fit"]["max_exponent"].get<double>(), 40.0);
  for (const auto& channel : document["channels"])
    for (const auto& lobe : channel["lobes"])
      for (const auto& n : lobe["exponent"]) EXPECT_LE(n.get<double>(), 40.0 * (1 + 1e-12)) << lobe;
  FitTableOptions automatic = fitOf(table, dir / "auto.json");
  automatic.fit.lobes = 2;
  automatic.fit.kind = LobeKindChoice::Mirror;
  fitTable(automatic);
  const auto automaticDocument = readJsonFile(dir / "auto.json");
  const double kept = automaticDocument["fit"]["max_exponent"].get<double>();
  EXPECT_TRUE(kept == 1e4 || kept == 3e3 || kept == 1e3) << kept;
  // A lowered cap starts from the fit under 1e4, clamped: the cap it records still bounds every lobe.
  for (const auto& channel : automaticDocument["channels"])
    for (const auto& lobe : channel["lobes"])
      for (const auto& n : lobe["exponent"]) EXPECT_LE(n.get<double>(), kept * (1 + 1e-12)) << lobe;
}

TEST(FitJob, TheReportIsAChartOfMeasuredAgainstFittedValues) {
  if (!findGnuplot()) GTEST_SKIP() << "gnuplot not installed (Debian: gnuplot-nox); skipping";
  // The report chart decoded (fit/fit_report.hpp): one panel per incident angle of the table, in
  // rows of at most 4 panels of 420 x 340 pixels under a 40-pixel title, and the table's R, G and B
  // drawn in their colours (#c0392b, #27ae60, #2e6fd0): each colour on many pixels, measured
  // points and fitted curves, not a blank or one-colour page.
  test::TempDir dir;
  const std::string path = test::sourcePath("data_samples/tables/synthetic_two_lobes.astm");
  FitTableOptions options = fitOf(path, dir / "f.json");
  options.fit.lobes = 2;
  options.fit.elevation = ElevationChoice::Constant;
  options.report = dir / "fit.png";
  const FitTableResult result = fitTable(options);
  EXPECT_NE(std::find(result.files.begin(), result.files.end(), dir / "fit.png"), result.files.end());
  const int panels = static_cast<int>(readAstm(path).incidentThetas().size());
  ASSERT_GE(panels, 2);
  const int columns = std::min(4, panels), rows = (panels + columns - 1) / columns;
  const Image report = readImage(dir / "fit.png");
  EXPECT_EQ(report.width(), 420 * columns);
  EXPECT_EQ(report.height(), 340 * rows + 40);
  const Rgb colours[3] = {Rgb(0xc0, 0x39, 0x2b) / 255.0, Rgb(0x27, 0xae, 0x60) / 255.0, Rgb(0x2e, 0x6f, 0xd0) / 255.0};
  int drawn[3] = {0, 0, 0};
  for (int y = 0; y < report.height(); ++y)
    for (int x = 0; x < report.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        // The PNG's 8-bit values, decoded to linear when the reader takes the file for sRGB
        // (image_io.hpp): encoded again before comparing, or compared as they are.
        const Rgb value = report.at(x, y).head<3>();
        Rgb encoded;
        for (int k = 0; k < 3; ++k)
          encoded[k] = value[k] <= 0.0031308 ? 12.92 * value[k] : 1.055 * std::pow(value[k], 1 / 2.4) - 0.055;
        drawn[c] += std::min((encoded - colours[c]).abs().maxCoeff(), (value - colours[c]).abs().maxCoeff()) < 0.04;
      }
  for (int c = 0; c < 3; ++c) EXPECT_GT(drawn[c], 100 * panels) << "channel " << c;
}

TEST(FitJob, DataSampleSpecsBake) {
  test::TempDir dir;
  const auto report = test::bakeSpec(test::sourcePath("data_samples/specs/measured_lobes.json"), dir.path());
  EXPECT_EQ(report["maps"].size(), 4u);
  for (const auto& map : report["maps"]) EXPECT_TRUE(fs::exists(map["output"].get<std::string>()));
  // The reflectance map at the centre (n = v, theta = 0) is the fit's mirror value there:
  // k_d / pi + C (n + 2) / (2 pi) with the parameters at the most normal elevation (t = 1).
  const auto fit = readJsonFile(test::sourcePath("data_samples/fits/synthetic_varying.json"));
  const double value = test::sampleAt(dir / "measured_lobes_reflectance.exr", Vec3(0, 0, 1))[1];
  const auto& g = fit["channels"][1];
  const double c = g["lobes"][0]["weight"][2], n = g["lobes"][0]["exponent"][2];
  EXPECT_NEAR(value, g["diffuse"].get<double>() / kPi + c * (n + 2) / (2 * kPi), 2e-3 * value);
}

TEST(FitJob, MerlTablesAreSampledOnTheCornellGridAndFitted) {
  test::TempDir dir;
  {
    // A Lambertian MERL file: every stored number 1500 -> BRDF (1, 1.15, 1.66) 1/sr.
    std::ofstream out(dir / "white.binary", std::ios::binary);
    const std::int32_t dims[3] = {90, 90, 180};
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
    const std::vector<double> channel(90 * 90 * 180, 1500.0);
    for (int c = 0; c < 3; ++c)
      out.write(reinterpret_cast<const char*>(channel.data()),
                static_cast<std::streamsize>(channel.size() * sizeof(double)));
  }
  fitTable(fitOf((dir / "white.binary").string(), dir / "fit.json"));
  const auto document = readJsonFile(dir / "fit.json");
  EXPECT_EQ(document["source"]["format"], "merl");
  EXPECT_EQ(document["source"]["samples"], 8 * 190);
  EXPECT_EQ(document["model"]["elevation"], "constant");
  EXPECT_EQ(document["model"]["lobes"], 1);
  const double scale[3] = {1.0, 1.15, 1.66};
  for (std::size_t c = 0; c < 3; ++c) {
    // f = k_d / pi + lobes: the fitted BRDF is the constant everywhere.
    const Vec3 wi = cornellDirection(0.7, 0.0), wo = cornellDirection(0.4, 2.0);
    EXPECT_NEAR(fitFormula(document, c, wi, wo), scale[c], 1e-3 * scale[c]);
  }
  const auto value = evaluate(dir / "white.binary", Vec3(0.3, 0, 0.95), Vec3(-0.2, 0.1, 0.97));
  ASSERT_EQ(value.size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(value[c], scale[c], 1e-12);
}

// The issue's acceptance: fit garnet red with auto lobes, then bake a spec that uses the fit.
TEST(FitJob, GarnetRedFitBakesAMap) {
  BRDFBAKE_REQUIRE_SHARED(table, "data/cornell/garnet_red.astm");
  test::TempDir dir;
  const FitTableResult fitted = fitTable(fitOf(table.string(), dir / "fit.json"));
  // Usable (every solve converged), and judged on held-out data against a Lambertian baseline: it
  // predicts the rows and elevations it never saw better than the best Lambertian fit does.
  EXPECT_TRUE(fitted.file.fit.usable()) << fitted.briefReport();
  ASSERT_TRUE(fitted.file.fit.heldOut) << fitted.briefReport();
  EXPECT_LT(fitted.file.fit.heldOut->score(), 1.0) << fitted.briefReport();
  std::ofstream(dir / "spec.json")
      << R"({"maps": [{"output": "garnet.exr", "parameterization": "sphere", "resolution": 64,
    "material": {"model": "lobes", "file": "fit.json"}}]})";
  test::bakeSpec(dir / "spec.json");
  EXPECT_TRUE(fs::exists(dir / "garnet.exr"));
  // Eval of the real table near a sample agrees with the file (interpolation returns samples).
  EXPECT_NEAR(evaluate(table, cornellDirection(0.872665, 0), cornellDirection(0.573513, 0))[0], 0.023025,
              1e-9);  // first row of the file, 400 nm
}

}  // namespace
}  // namespace brdfbake
