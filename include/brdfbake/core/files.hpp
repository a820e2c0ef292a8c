#pragma once
/// @file
/// How brdfbake touches the file system, in one place: inputs are read whole and checked, outputs
/// appear atomically (whole or not at all), temporaries never outlive the process (even on an
/// interrupt), and a command's planned files are checked against each other before any work.
/// The guarantees are listed in README.md ("Guarantees"); tests/core/test_files.cpp pins them.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// `text` for an error message: at most `limit` characters, the middle elided and the full length
/// given ("aaaa...zzzz (52428800 characters)"), so a hostile 50 MB name is never echoed whole.
std::string shortenForMessage(std::string_view text, std::size_t limit = 200);

/// Checks that `path` is an existing regular file (following symlinks) and returns its size.
/// Throws Error(Io) "<path>: no such file" or "<path>: is a folder, not a file" (`what` names the
/// role, e.g. "measured table").
std::uintmax_t requireInputFile(const std::filesystem::path& path, const std::string& what = "input file");

/// Reads a whole file (requireInputFile first). Files over `maxBytes` are refused with Error(Resource).
std::string readTextFile(const std::filesystem::path& path, const std::string& what = "input file",
                         std::uintmax_t maxBytes = std::uintmax_t{1} << 30);

/// A file that appears whole or not at all. Write to temporaryPath() (a hidden sibling of the
/// target with the same extension), then commit() renames it over the target. Until committed the
/// temporary is registered for removeTemporaryFilesNow() and the destructor removes it.
class AtomicOutput {
 public:
  /// Creates the target's folder if needed. Throws Error(Io) if the target is a folder or its
  /// folder cannot be created.
  explicit AtomicOutput(std::filesystem::path target);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporaryPath() const { return temporary_; }
  /// Moves the finished temporary into place. Throws Error(Io) naming the target.
  void commit();

 private:
  std::filesystem::path target_, temporary_;
  int slot_ = -1;
  bool committed_ = false;
};

/// A scratch file in the system's temporary folder (a gnuplot script, a log), registered like an
/// AtomicOutput's temporary and removed by the destructor.
class ScratchFile {
 public:
  /// A fresh name "/tmp/brdfbake-<pid>-<n><suffix>"; nothing is created yet.
  explicit ScratchFile(const std::string& suffix);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int slot_ = -1;
};

/// Writes `bytes` to `target` through an AtomicOutput.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

/// Removes every registered temporary file. Async-signal-safe (unlink only): the CLI calls it from
/// its SIGINT/SIGTERM/SIGHUP handler.
void removeTemporaryFilesNow() noexcept;

/// The files a command reads and writes, checked before any work starts (check()):
///   - no output is an input, and no two outputs are the same file; paths are compared after
///     resolving "..", symlinks and hard links;
///   - with an output folder, every output lies inside it;
///   - every output can be written: it is not a folder, and its folder exists or can be created
///     in a writable place.
/// Each file carries a role ("spec", "maps[1].output", "--report") that the messages name.
class FilePlan {
 public:
  explicit FilePlan(std::optional<std::filesystem::path> outputFolder = std::nullopt);
  void addInput(const std::filesystem::path& file, std::string role);
  void addOutput(const std::filesystem::path& file, std::string role);
  /// Throws Error(InvalidArgument) for the first conflict, naming both roles and the file.
  void check() const;

  struct Entry {
    std::filesystem::path file;
    std::string role;
  };
  const std::vector<Entry>& inputs() const { return inputs_; }
  const std::vector<Entry>& outputs() const { return outputs_; }

 private:
  std::optional<std::filesystem::path> outputFolder_;
  std::vector<Entry> inputs_, outputs_;
};

/// STEM<suffix>.EXT beside `path` ("out/sky.exr", "_mip2" -> "out/sky_mip2.exr"): how every derived
/// output (mip levels, cube faces, elevation slices, Fresnel maps, chart pages) is named.
std::filesystem::path siblingWithSuffix(const std::filesystem::path& path, const std::string& suffix);

/// The file a path resolves to, for comparisons: absolute, "..", "." and symlinks of its existing
/// part resolved.
std::filesystem::path resolvedPath(const std::filesystem::path& path);

/// True if `a` and `b` name the same file (resolvedPath, or the same inode when both exist).
bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace brdfbake
