// Reproducers of fuzzer findings (tests/stability/fuzz_regressions/<target>/<name>) and the committed
// fuzz seeds (fuzz/corpus/<target>/), fed through the fuzz targets' own entry points
// (fuzz/fuzz_targets.hpp): each input must parse or throw brdfbake::Error naming the file it was
// read from; no crash, no sanitizer report (in the fuzz build), no other exception. Inputs run with
// the fuzzers' memory budget (BRDFBAKE_MEMORY_LIMIT=512M unless set).
#define BRDFBAKE_FUZZ_SOURCE_DIR BRDFBAKE_SOURCE_DIR
#include "fuzz_targets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <vector>

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

std::vector<std::uint8_t> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Files under <folder>/<target>/, sorted; none if the folder is absent.
std::vector<fs::path> inputsOf(const fs::path& folder, const std::string& target) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(folder / target, ec)) return files;
  for (const auto& entry : fs::directory_iterator(folder / target))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Runs one input; a failure message names the input.
void expectParsesOrNamedError(const fuzzing::Target& target, const fs::path& input) {
  SCOPED_TRACE(input.string());
  const std::vector<std::uint8_t> bytes = readBytes(input);
  const fs::path scratch = fuzzing::scratchDir() / target.fileName(bytes.data(), bytes.size());
  const fuzzing::FuzzMemoryLimit limit;  // the fuzzers' memory budget, for this input only
  try {
    fuzzing::runTarget(target, bytes.data(), bytes.size());
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(scratch.filename().string()), std::string::npos)
        << "the message does not name the file: " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than brdfbake::Error: " << e.what();
  } catch (...) {
    ADD_FAILURE() << "threw something other than brdfbake::Error";
  }
}

class FuzzTarget : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzTarget, RegressionsParseOrThrowErrorNamingTheFile) {
  const fuzzing::Target* target = fuzzing::findTarget(GetParam());
  ASSERT_NE(target, nullptr);
  const auto inputs = inputsOf(fs::path(BRDFBAKE_SOURCE_DIR) / "tests/stability/fuzz_regressions", GetParam());
  for (const fs::path& input : inputs) expectParsesOrNamedError(*target, input);
  if (inputs.empty()) GTEST_SKIP() << "no reproducers for " << GetParam();
}

TEST_P(FuzzTarget, SeedsParseOrThrowErrorNamingTheFile) {
  const fuzzing::Target* target = fuzzing::findTarget(GetParam());
  ASSERT_NE(target, nullptr);
  const auto inputs = inputsOf(fs::path(BRDFBAKE_SOURCE_DIR) / "fuzz/corpus", GetParam());
  EXPECT_FALSE(inputs.empty()) << "fuzz/corpus/" << GetParam() << " has no seeds";
  for (const fs::path& input : inputs) expectParsesOrNamedError(*target, input);
}

INSTANTIATE_TEST_SUITE_P(Fuzz, FuzzTarget,
                         ::testing::Values("spec", "fit", "astm", "pbrt", "merl", "mat", "image", "ktx2", "ktx1",
                                           "dds"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace brdfbake
