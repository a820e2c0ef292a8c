#pragma once
// What the run-layer tests share: each command's computation called through its library job, the
// way a renderer or a script calls it (brdfbake::run), with the same JSON the tool prints.
#include <brdfbake/run/describe_output.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/sample_output.hpp>
#include <brdfbake/run/spec_runner.hpp>
#include <brdfbake/spec/spec.hpp>

#include <string>

#include "test_support.hpp"

namespace brdfbake::test {

/// `brdfbake sample PATH --dir D`: the value a renderer looks up (RGB).
inline Rgb sampleAt(const std::filesystem::path& path, const Vec3& direction, std::optional<double> cosView = {}) {
  SampleOptions options;
  options.source.path = path;
  options.source.cosView = cosView;
  options.directions = {direction};
  return sampleOutput(options).lookups.at(0).value.head<3>();
}

/// `brdfbake info PATH --json`.
inline nlohmann::json infoOf(const std::filesystem::path& path) { return describeOutput(path).description; }

/// `brdfbake bake SPEC --out-dir DIR --json` (DIR empty: the spec's folder). Expects no map to fail.
inline nlohmann::json bakeSpec(const std::filesystem::path& spec, const std::filesystem::path& outDir = {}) {
  SpecRunOptions options;
  options.spec = spec;
  options.outDir = outDir;
  const SpecRunResult result = runSpec(options);
  EXPECT_EQ(result.failed(), 0) << result.briefReport();
  return result.toJson();
}

/// `brdfbake prefilter ENVIRONMENT --lobe LOBE --to TO --resolution RESOLUTION -o OUTPUT`, the
/// other fields at their defaults (run it with runPrefilter). LOBE as the tool takes it (parseLobeArgument).
inline PrefilterFiles prefilterFiles(const std::filesystem::path& environment, const std::string& lobe,
                                     const std::string& to, int resolution, const std::filesystem::path& output) {
  PrefilterFiles files;
  files.environment = environment;
  const LobeArgument parsed = parseLobeArgument(lobe, ".");
  if (const auto* analytic = std::get_if<PrefilterLobe>(&parsed.lobe)) {
    files.request.lobe = *analytic;
  } else {
    files.request.lobeModel = std::get<std::shared_ptr<const LobeModel>>(parsed.lobe);
    files.request.lobeName = lobe;
  }
  files.request.parameterization = parseParameterizationKind(to);
  files.request.resolution = resolution;
  files.outputs.files = {output};
  return files;
}

}  // namespace brdfbake::test
