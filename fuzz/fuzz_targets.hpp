#pragma once
// The fuzz targets' entry points, shared by the libFuzzer executables (fuzz_<name>.cpp) and the
// regression test (tests/stability/test_fuzz_regressions.cpp), so a reproducer goes through exactly
// the code path that found it. Every reader takes a path: the bytes are written to a per-process
// scratch file under /dev/shm (or the system temp folder) with the extension the reader expects,
// then the reader is called. brdfbake::Error is the expected outcome for a bad input; anything
// else (other exceptions, crashes, sanitizer reports) is a finding.
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/spec/spec.hpp>

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

namespace brdfbake::fuzzing {

struct Target {
  const char* name;
  /// The scratch file's name (relative to the scratch folder); the image target picks the
  /// extension from the bytes.
  std::string (*fileName)(const std::uint8_t* data, std::size_t size);
  /// Calls the reader on the scratch file (parse only, never writes).
  void (*read)(const std::filesystem::path& file);
};

/// The memory budget (core/memory_budget.hpp) the targets run with unless BRDFBAKE_MEMORY_LIMIT is
/// set: well under libFuzzer's -rss_limit_mb=2048, so a header asking for too much must end in
/// Error(Resource) from the budget check, not in an allocation libFuzzer reports as out-of-memory.
inline constexpr const char* kFuzzMemoryLimit = "512M";

/// Sets BRDFBAKE_MEMORY_LIMIT to kFuzzMemoryLimit while it lives, unless it is set already.
class FuzzMemoryLimit {
 public:
  FuzzMemoryLimit() : set_(std::getenv("BRDFBAKE_MEMORY_LIMIT") == nullptr) {
    if (set_) ::setenv("BRDFBAKE_MEMORY_LIMIT", kFuzzMemoryLimit, 1);
  }
  ~FuzzMemoryLimit() {
    if (set_) ::unsetenv("BRDFBAKE_MEMORY_LIMIT");
  }
  FuzzMemoryLimit(const FuzzMemoryLimit&) = delete;
  FuzzMemoryLimit& operator=(const FuzzMemoryLimit&) = delete;

 private:
  bool set_;
};

/// /dev/shm/brdfbake-fuzz-<pid> (the system temp folder if /dev/shm is absent), created once;
/// removed at exit. For specs, <scratch>/fits links to data_samples/fits when the source folder is
/// known (BRDFBAKE_FUZZ_SOURCE_DIR), so "lobes" materials that name ../fits/*.json resolve.
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path d = base / ("brdfbake-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(d / "specs", ec);
#ifdef BRDFBAKE_FUZZ_SOURCE_DIR
    const fs::path fits = fs::path(BRDFBAKE_FUZZ_SOURCE_DIR) / "data_samples" / "fits";
    if (fs::is_directory(fits, ec) && !fs::exists(d / "fits", ec)) fs::create_directory_symlink(fits, d / "fits", ec);
#endif
    static std::string removeAtExit = d.string();
    std::atexit([] {
      std::error_code e;
      std::filesystem::remove_all(removeAtExit, e);
    });
    return d;
  }();
  return dir;
}

/// Writes the bytes to <scratch>/<name>, replacing what was there; returns the path.
inline std::filesystem::path writeScratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = scratchDir() / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror(path.c_str());
    std::abort();  // the harness itself is broken: say so loudly
  }
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

namespace detail {
inline std::string fixed(const char* name) { return name; }
// Texture containers: every level decoded (readTexture), then level 0 as readImage returns it.
inline void readContainer(const std::filesystem::path& f) {
  (void)readTexture(f);
  (void)readImage(f);
}
inline std::string imageName(const std::uint8_t* data, std::size_t size) {
  // Real files keep their own format (so seeds work as they are); anything else by the first
  // byte, modulo 4. readImage itself goes by the bytes (image_header.cpp checks every header first).
  static const char kExrMagic[] = {'\x76', '\x2f', '\x31', '\x01'};
  if (size >= 2 && data[0] == '#' && data[1] == '?') return "input.hdr";
  if (size >= 4 && std::memcmp(data, kExrMagic, 4) == 0) return "input.exr";
  if (size >= 4 && std::memcmp(data, "\x89PNG", 4) == 0) return "input.png";
  if (size >= 2 && (std::memcmp(data, "II", 2) == 0 || std::memcmp(data, "MM", 2) == 0)) return "input.tif";
  static const char* const kNames[] = {"input.exr", "input.hdr", "input.png", "input.tif"};
  return size > 0 ? kNames[data[0] % 4] : "input.exr";
}
}  // namespace detail

inline const Target kTargets[] = {
    {"spec", [](const std::uint8_t*, std::size_t) { return detail::fixed("specs/spec.json"); },
     [](const std::filesystem::path& f) { (void)loadBakeSpec(f); }},
    {"fit", [](const std::uint8_t*, std::size_t) { return detail::fixed("fit.json"); },
     [](const std::filesystem::path& f) { (void)readFitFile(f); }},
    {"astm", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.astm"); },
     [](const std::filesystem::path& f) { (void)readAstm(f); }},
    {"pbrt", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.brdf"); },
     [](const std::filesystem::path& f) { (void)readPbrt(f); }},
    {"merl", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.binary"); },
     [](const std::filesystem::path& f) { (void)readMerl(f); }},
    {"mat", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.mat"); },
     [](const std::filesystem::path& f) { (void)readMat(f); }},
    {"image", detail::imageName, [](const std::filesystem::path& f) { (void)readImage(f); }},
    {"ktx2", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.ktx2"); }, detail::readContainer},
    {"ktx1", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.ktx"); }, detail::readContainer},
    {"dds", [](const std::uint8_t*, std::size_t) { return detail::fixed("input.dds"); }, detail::readContainer},
};

inline const Target* findTarget(std::string_view name) {
  for (const Target& t : kTargets)
    if (name == t.name) return &t;
  return nullptr;
}

/// Writes the input where the target reads it and runs the reader; returns the scratch path.
/// Error propagates (callers decide what to do with it).
inline std::filesystem::path runTarget(const Target& target, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = writeScratch(target.fileName(data, size), data, size);
  target.read(file);
  return file;
}

/// The body of LLVMFuzzerTestOneInput: only brdfbake::Error is caught.
inline int fuzzOne(std::string_view name, const std::uint8_t* data, std::size_t size) {
  static const Target* target = findTarget(name);
  static const FuzzMemoryLimit limit;
  try {
    runTarget(*target, data, size);
  } catch (const Error&) {
  }
  return 0;
}

}  // namespace brdfbake::fuzzing

#define BRDFBAKE_FUZZ_TARGET(NAME)                                                    \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return ::brdfbake::fuzzing::fuzzOne(NAME, data, size);                            \
  }
