// The run layer: each job called as a renderer or a script would, checked against values the code
// did not produce (analytic lobes, a furnace, the files on disk), and the rules every job keeps
// (validated first, nothing written on bad input, progress, cancellation).
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/chart.hpp>
#include <brdfbake/run/convert_output.hpp>
#include <brdfbake/run/describe_output.hpp>
#include <brdfbake/run/evaluate.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/sample_output.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <optional>

#include "run_support.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// Phong n = 50 lit from the eye in a sphere map: the map holds max(0, r_z)^50 (Zimmons & Bastos 1999 section 5).
nlohmann::json phongEyeSpec(const std::string& output) {
  return {{"maps",
           {{{"output", output},
             {"parameterization", "sphere"},
             {"resolution", 128},
             {"material", {{"model", "phong"}, {"specular", {1, 1, 1}}, {"exponent", 50}}},
             {"lights", {{{"direction", "eye"}, {"color", {1, 1, 1}}}}}}}}};
}

TEST(RunSpec, BakesADocumentSpecIntoTheOutputFolderAndMatchesTheAnalyticLobe) {
  TempDir dir;
  SpecRunOptions options;
  options.document = phongEyeSpec("phong.exr");
  options.outDir = dir.path();
  const SpecRunResult result = runSpec(options);
  ASSERT_EQ(result.maps.size(), 1u);
  EXPECT_TRUE(result.maps[0].written);
  EXPECT_FALSE(result.firstError);
  EXPECT_EQ(result.maps[0].entry["status"], "written");
  ASSERT_TRUE(fs::exists(dir / "phong.exr"));
  EXPECT_EQ(result.files.front(), dir / "phong.exr");
  // A lookup 20 degrees off the view: r_z = cos(20 deg).
  const MapFile map = readMap(dir / "phong.exr");
  const Vec3 r(std::sin(20 * kPi / 180), 0.0, std::cos(20 * kPi / 180));
  const double expected = std::pow(r.z(), 50.0);
  EXPECT_NEAR(sampleBilinear(map.image, *map.parameterization, r)[0], expected, 0.01);
  EXPECT_NE(result.briefReport().find("wrote " + (dir / "phong.exr").string()), std::string::npos);
}

TEST(RunSpec, RefusesCollidingOutputsBeforeWritingAnything) {
  TempDir dir;
  nlohmann::json spec = phongEyeSpec("a.exr");
  spec["maps"].push_back(spec["maps"][0]);
  spec["maps"][1]["output"] = "b.exr";
  spec["maps"][1]["fresnel_table_output"] = "a.exr";  // not a fresnel material: refused at parse
  SpecRunOptions options;
  options.document = spec;
  options.outDir = dir.path();
  EXPECT_THROW(runSpec(options), Error);
  EXPECT_TRUE(test::filesIn(dir.path()).empty());
  spec["maps"][1].erase("fresnel_table_output");
  spec["maps"][1]["output"] = "a.exr";  // two maps, one file
  options.document = spec;
  try {
    runSpec(options);
    FAIL() << "two maps writing one file were accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("maps[1]"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(test::filesIn(dir.path()).empty());
}

TEST(RunSpec, AMapThatFailsWhileBeingMadeDoesNotStopTheOthers) {
  TempDir dir;
  nlohmann::json spec = phongEyeSpec("ok.exr");
  nlohmann::json unreachable = spec["maps"][0];
  unreachable["output"] = "auto.exr";
  unreachable["resolution"] = 16;
  unreachable["samples_per_texel"] = "auto";  // a quick search...
  unreachable["max_error"] = 1e-9;            // ...that no candidate meets: fails after validation
  spec["maps"].insert(spec["maps"].begin(), unreachable);
  SpecRunOptions options;
  options.document = spec;
  options.outDir = dir.path();
  const SpecRunResult result = runSpec(options);
  ASSERT_EQ(result.maps.size(), 2u);
  EXPECT_FALSE(result.maps[0].written);
  EXPECT_TRUE(result.maps[1].written);
  EXPECT_EQ(result.failed(), 1);
  ASSERT_TRUE(result.firstError);
  EXPECT_NE(std::string(result.firstError->what()).find("no configuration meets max_error"), std::string::npos);
  EXPECT_EQ(test::filesIn(dir.path()), std::vector<std::string>{"ok.exr"});
  EXPECT_EQ(result.toJson()["maps"][0]["status"], "failed");
  EXPECT_NE(result.briefReport().find("1 of 2 maps failed; the others were written"), std::string::npos);
}

TEST(RunSpec, ReportsProgressPerMapEndingAtOneAndACancellingSinkLeavesNothing) {
  TempDir dir;
  SpecRunOptions options;
  options.document = phongEyeSpec("phong.exr");
  options.outDir = dir.path();
  std::mutex mutex;
  std::map<std::string, double> last;
  runSpec(options, Context({.progress = [&](const std::string& task, double fraction) {
            std::lock_guard lock(mutex);
            EXPECT_GE(fraction, last[task]);
            last[task] = fraction;
          }}));
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last.begin()->first, "maps[0] phong.exr");
  EXPECT_DOUBLE_EQ(last.begin()->second, 1.0);

  TempDir other;
  options.outDir = other.path();
  const Context throwing({.progress = [](const std::string&, double fraction) {
    if (fraction > 0.3) throw std::runtime_error("cancelled");
  }});
  EXPECT_THROW(runSpec(options, throwing), std::runtime_error);
  EXPECT_TRUE(test::filesIn(other.path()).empty());
  // Context::cancel from another thread (here the sink, as Python's Ctrl-C handler does): Cancelled,
  // which no map's failure report takes for a failure, and nothing left.
  std::optional<Context> cancelling;
  cancelling.emplace(Context::Options{.progress = [&](const std::string&, double fraction) {
    if (fraction > 0.3) cancelling->cancel();
  }});
  EXPECT_THROW(runSpec(options, *cancelling), Cancelled);
  EXPECT_TRUE(test::filesIn(other.path()).empty());
}

TEST(RunSpec, OptionsAreValidatedBeforeAnyWork) {
  SpecRunOptions options;
  EXPECT_THROW(planSpec(options), Error);  // neither a file nor a document
  options.document = phongEyeSpec("x.exr");
  options.spec = "also_a_file.json";
  EXPECT_THROW(planSpec(options), Error);  // both
}

TEST(PrefilterJob, AFurnaceGivesTheLobeMassAtEveryLookup) {
  // A constant environment of radiance 1: a normalised Phong lobe integrates to 1, and so does irradiance (E/pi).
  TempDir dir;
  const fs::path furnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");
  for (const auto& [lobe, mass] : {std::pair{"phong:40", 1.0}, std::pair{"irradiance", 1.0}}) {
    const fs::path output = dir / (std::string(lobe == std::string("irradiance") ? "irr" : "phong") + ".exr");
    const MapResult result = runPrefilter(test::prefilterFiles(furnace, lobe, "cube", 16, output));
    EXPECT_TRUE(result.written);
    EXPECT_EQ(result.entry["environment"]["file"], "furnace_latlong.exr");  // the name: no folder of this machine
    SampleOptions sample;
    sample.source.path = output;
    sample.directions = {Vec3(1, 2, 3), Vec3(0, -1, 0), Vec3(-0.3, 0.1, -1)};
    for (const auto& lookup : sampleOutput(sample).lookups) EXPECT_NEAR(lookup.value[1], mass, 2e-3 * mass) << lobe;
  }
}

TEST(PrefilterJob, TheRequestIsValidatedFirstAndItsErrorsNameItsFields) {
  TempDir dir;
  const fs::path sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  auto fieldOf = [&](const std::function<void(PrefilterFiles&)>& change) {
    PrefilterFiles files = test::prefilterFiles(sky, "phong:10", "cube", 16, dir / "out.exr");
    change(files);
    try {
      runPrefilter(files);
    } catch (const Error& e) {
      return e.field().empty() ? std::string("(no field) ") + e.what() : e.field();
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.request.resolution = 0; }), "resolution");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.request.maxError = 0.7; }), "max_error");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) {
              f.request.glossChain = GlossChain{GlossChain::Lobe::Phong, 10, 1, 6};
            }),
            "gloss_chain");  // 6 levels from 16 texels: 16, 8, 4, 2, 1 are 5
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) {
              f.request.lobe = PrefilterLobe::irradiance(),
              f.request.fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
            }),
            "fresnel");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.request.combine = FresnelCombine::Mix; }), "combine");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.request.sh = true; }), "sh");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.request.view = Vec3(0, 1, 0); }), "view");  // a cube has none
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.outputs.files.clear(); }), "outputs");
  EXPECT_EQ(fieldOf([](PrefilterFiles& f) { f.outputs.texelFormat = TexelFormat::Rgb9e5; }), "texel_format");
  EXPECT_TRUE(test::filesIn(dir.path()).empty());
  // In memory, without an environment.
  PrefilterRequest bare;
  EXPECT_EQ(test::errorOf([&] { prefilterEnvironment(bare); }), "environment: no environment given");
}

TEST(EvaluateJob, APhongMaterialFileGivesItsFormula) {
  // {"model": "phong"} lit by one light of colour 1: shade = d (n.l) + s (r.l)^N, so the BRDF is
  // d + s (r.l)^N / (n.l) with r the mirrored view.
  TempDir dir;
  const fs::path material = dir / "phong.json";
  std::ofstream(material) << R"({"model": "phong", "diffuse": [0.2, 0.2, 0.2], "specular": [1, 1, 1], "exponent": 20})";
  EvaluateOptions options;
  options.model = material;
  options.wi = Vec3(std::sin(0.5), 0.0, std::cos(0.5));
  options.wo = Vec3(-std::sin(0.4), 0.0, std::cos(0.4));
  const EvaluateResult result = evaluateBrdf(options);
  ASSERT_EQ(result.rows.size(), 1u);
  const double rl = std::cos(0.1);  // the mirrored view is 0.1 rad from the light
  const double expected = 0.2 + std::pow(rl, 20.0) / std::cos(0.5);
  EXPECT_NEAR((*result.rows[0].value)[0], expected, 1e-9 * expected);
  EXPECT_EQ(result.toJson()["kind"], "material");
}

TEST(EvaluateJob, APairsFileIsCheckedWholeAndNamesTheLine) {
  TempDir dir;
  std::ofstream(dir / "phong.json") << R"({"model": "phong", "specular": [1, 1, 1], "exponent": 20})";
  std::ofstream(dir / "pairs.txt") << "# comment\n0.5 0 0.4 3.14159\n0.5 0 oops 0\n";
  EvaluateOptions options;
  options.model = dir / "phong.json";
  options.pairs = dir / "pairs.txt";
  try {
    evaluateBrdf(options);
    FAIL() << "a bad pairs line was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pairs.txt:3"), std::string::npos) << e.what();
  }
  options.pairs = "/dev/zero";  // never ends: refused, not read
  EXPECT_THROW(evaluateBrdf(options), Error);
}

TEST(OutputJobs, ConvertDescribeAndSampleAgreeWithTheAnalyticLobe) {
  TempDir dir;
  SpecRunOptions bake;
  bake.document = phongEyeSpec("phong.exr");
  bake.outDir = dir.path();
  runSpec(bake);
  ConvertOptions convert;
  convert.source.path = dir / "phong.exr";
  convert.to = ParameterizationKind::Paraboloid;
  convert.resolution = 128;
  convert.outputs.files = {dir / "phong_paraboloid.exr"};
  const ConvertResult converted = convertOutput(convert);
  EXPECT_EQ(converted.files.front(), convert.outputs.files.front());
  const OutputDescription described = describeOutput(convert.outputs.files.front());
  EXPECT_EQ(described.description["parameterization"], "paraboloid");
  EXPECT_EQ(described.description["spec"]["converted_from"]["file"],
            convert.source.path.filename().string());  // no folder
  SampleOptions sample;
  sample.source.path = convert.outputs.files.front();
  const Vec3 r = Vec3(0.2, -0.1, 1.0).normalized();
  sample.directions = {r};
  EXPECT_NEAR(sampleOutput(sample).lookups[0].value[0], std::pow(r.z(), 50.0), 0.02);
  sample.source.cosView = 0.5;  // a map is looked up by direction alone
  EXPECT_THROW(sampleOutput(sample), Error);
}

TEST(ChartJob, ErrorsFallWithResolutionAndTheFrontHoldsTheFastestAndTheMostAccurate) {
  TempDir dir;
  std::ofstream(dir / "spec.json") << phongEyeSpec("phong.exr").dump();
  ChartOptions options;
  options.spec = dir / "spec.json";
  options.resolutions = {16, 64, 256};
  options.samplesPerTexel = {4};
  options.parameterizations = {ParameterizationKind::Sphere};
  options.lookups = 2000;
  options.csv = dir / "points.csv";
  const ChartResult result = chartSpec(options);
  ASSERT_EQ(result.points.size(), 3u);
  EXPECT_GT(result.points[0].bound, result.points[2].bound);
  // The most accurate point and the fastest point are never dominated.
  const auto accurate = std::min_element(result.points.begin(), result.points.end(),
                                         [](const auto& a, const auto& b) { return a.bound < b.bound; });
  const auto fastest = std::min_element(result.points.begin(), result.points.end(),
                                        [](const auto& a, const auto& b) { return a.seconds < b.seconds; });
  EXPECT_TRUE(accurate->pareto);
  EXPECT_TRUE(fastest->pareto);
  std::ifstream csv(dir / "points.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 4);  // header and three points
}

}  // namespace
}  // namespace brdfbake
