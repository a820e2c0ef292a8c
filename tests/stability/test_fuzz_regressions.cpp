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

// Runs one input that may fail; a failure must be brdfbake::Error naming the file.
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

// The seeds that are bad on purpose (a MERL file is 35 MB, far over the fuzzer's max_len, so its
// seeds are a header alone and a header without its data): each must be refused with an Error
// naming the file and saying why. Every other seed is a valid file and must parse.
struct BadSeed {
  const char* target;
  const char* file;
  const char* why;  ///< part of the message
};
constexpr BadSeed kBadSeeds[] = {{"merl", "bad_dims.binary", "must be exactly 34992012 bytes"},
                                 {"merl", "header.binary", "this file has 44"}};

const BadSeed* badSeed(const std::string& target, const fs::path& input) {
  for (const BadSeed& b : kBadSeeds)
    if (target == b.target && input.filename() == b.file) return &b;
  return nullptr;
}

// The targets that have reproducers (a folder under tests/stability/fuzz_regressions/). Targets
// without any (astm, pbrt, merl so far: their fuzzers found nothing) are not instantiated, so no
// test is skipped for ever; a reproducer added for them is picked up by its folder.
std::vector<std::string> targetsWithReproducers() {
  std::vector<std::string> names;
  for (const fuzzing::Target& t : fuzzing::kTargets)
    if (!inputsOf(fs::path(BRDFBAKE_SOURCE_DIR) / "tests/stability/fuzz_regressions", t.name).empty())
      names.push_back(t.name);
  return names;
}

class FuzzRegressions : public ::testing::TestWithParam<std::string> {};
class FuzzSeeds : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzRegressions, RegressionsParseOrThrowErrorNamingTheFile) {
  const fuzzing::Target* target = fuzzing::findTarget(GetParam());
  ASSERT_NE(target, nullptr);
  const auto inputs = inputsOf(fs::path(BRDFBAKE_SOURCE_DIR) / "tests/stability/fuzz_regressions", GetParam());
  ASSERT_FALSE(inputs.empty());
  for (const fs::path& input : inputs) expectParsesOrNamedError(*target, input);
}

TEST_P(FuzzSeeds, SeedsParseAndBadOnesAreRefusedNamingTheFile) {
  const fuzzing::Target* target = fuzzing::findTarget(GetParam());
  ASSERT_NE(target, nullptr);
  const auto inputs = inputsOf(fs::path(BRDFBAKE_SOURCE_DIR) / "fuzz/corpus", GetParam());
  ASSERT_FALSE(inputs.empty()) << "fuzz/corpus/" << GetParam() << " has no seeds";
  for (const fs::path& input : inputs) {
    SCOPED_TRACE(input.string());
    const std::vector<std::uint8_t> bytes = readBytes(input);
    const fs::path scratch = fuzzing::scratchDir() / target->fileName(bytes.data(), bytes.size());
    const fuzzing::FuzzMemoryLimit limit;
    const BadSeed* bad = badSeed(GetParam(), input);
    try {
      fuzzing::runTarget(*target, bytes.data(), bytes.size());
      EXPECT_EQ(bad, nullptr) << "a bad seed was accepted";
    } catch (const Error& e) {
      ASSERT_NE(bad, nullptr) << "a valid seed was refused: " << e.what();
      EXPECT_NE(std::string(e.what()).find(scratch.filename().string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(bad->why), std::string::npos) << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Fuzz, FuzzRegressions, ::testing::ValuesIn(targetsWithReproducers()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });
INSTANTIATE_TEST_SUITE_P(Fuzz, FuzzSeeds,
                         ::testing::Values("spec", "fit", "astm", "pbrt", "merl", "mat", "image", "ktx2", "ktx1",
                                           "dds"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace brdfbake
