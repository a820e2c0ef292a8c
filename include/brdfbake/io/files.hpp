#pragma once
/// @file
/// How brdfbake touches the file system, in one place: inputs are read whole and checked, outputs
/// appear atomically (whole or not at all), temporaries never outlive the process (even on an
/// interrupt), and a command's planned files are checked against each other before any work.
/// The guarantees are listed in README.md ("Guarantees"); tests/core/test_files.cpp pins them.

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// The former name of printable() (core/printable.hpp), kept while cli/ still calls it.
inline std::string shortenForMessage(std::string_view text, std::size_t limit = kPrintableLimit) {
  return printable(text, limit);
}

/// Throws Error(InvalidArgument) "<role>: <path>: contains a NUL character" if it does: the system
/// would cut the name there and read or write another file. FilePlan::check, requireInputFile and
/// AtomicOutput call it, so every front (JSON, Python, flags) goes through it.
void requireNoNul(const std::filesystem::path& path, const std::string& role);

/// Checks that `path` is an existing regular file (following symlinks) and returns its size.
/// Throws Error(Io) "<path>: no such file", "<path>: is a folder, not a file" or "<path>: is a FIFO
/// (named pipe), not a regular file" (`what` names the role, e.g. "measured table"): devices, FIFOs
/// and sockets never end or block, so no reader takes them.
std::uintmax_t requireInputFile(const std::filesystem::path& path, const std::string& what = "input file");

/// An input file opened once: its type and size are those of the open file (fstat), and every
/// read goes through the same descriptor, so a file replaced meanwhile (an atomic rename) is read
/// whole as the old file, never half old and half new. Throws as requireInputFile, and Error(Io)
/// "<path>: not a regular file" should a device take the file's place before it opens.
class InputFile {
 public:
  InputFile(const std::filesystem::path& path, const std::string& what);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::uintmax_t size() const { return size_; }
  int descriptor() const { return fd_; }
  /// A name for this open file (/proc/self/fd/N) for a library that opens files by name; the
  /// path itself where /proc is not mounted.
  std::filesystem::path openName() const;
  /// Up to `count` bytes from `offset` (fewer at the end of the file).
  std::string read(std::uintmax_t offset, std::size_t count) const;

 private:
  std::filesystem::path path_;
  std::string what_;  ///< the role named in messages ("image", "measured table")
  std::uintmax_t size_ = 0;
  int fd_ = -1;
};

/// Reads a whole file (requireInputFile first), never more than `maxBytes` (a file that grows while
/// read included): Error(Resource) beyond.
std::string readTextFile(const std::filesystem::path& path, const std::string& what = "input file",
                         std::uintmax_t maxBytes = std::uintmax_t{1} << 30);

/// Throws Error(`kind`) naming `path` (and `role`, when given) unless it is absent or a regular file.
/// A symbolic link is refused, not followed: outputs replace only regular files, never a device
/// node, FIFO, socket, folder or the file a link points to.
void requireReplaceableOutput(const std::filesystem::path& path, Error::Kind kind, const std::string& role = {});

/// "a regular file", "a folder", "a symbolic link", "a character device", "a FIFO (named pipe)", ...
std::string describeFileType(std::filesystem::file_type type);

/// The system's text for an errno value ("No space left on device").
std::string errnoText(int error);

/// A file that appears whole or not at all: every output of brdfbake (images of every format,
/// sidecars, fit.json, reports, charts, CSV) is committed through one. Write the temporary (a hidden
/// sibling of the target with the same extension) with write(), or through the descriptor open()
/// gives, or by its path (temporaryPath(), for a program that writes it); then commit() checks the
/// close and renames it over the target. Until committed the temporary is registered for
/// removeTemporaryFilesNow() and the destructor removes it. Every failure is Error(Io) naming the
/// target, never the temporary: "out.png: write failed: No space left on device (disk full)".
class AtomicOutput {
 public:
  /// Creates the target's folder if needed. Throws Error(Io) if the target exists and is not a
  /// regular file (requireReplaceableOutput), or its folder cannot be created.
  explicit AtomicOutput(std::filesystem::path target);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporaryPath() const { return temporary_; }
  /// Creates the temporary (exclusively; read-write) and returns its descriptor, which stays owned
  /// by this object; later calls return the same descriptor.
  int open();
  /// Appends `bytes` to the temporary (open() first), checking every write.
  void write(std::string_view bytes);
  /// Closes the temporary's descriptor, checking the close (a deferred write error shows here).
  void close();
  /// The Error(Io) for a failed write with errno value `error`, naming the target.
  Error writeFailed(int error) const;
  /// close(), then moves the finished temporary into place, after checking again that the target is
  /// absent or a regular file. Throws Error(Io) naming the target.
  void commit();

 private:
  std::filesystem::path target_, temporary_;
  int slot_ = -1;
  int fd_ = -1;
  bool committed_ = false;
};

/// Files committed as one set. While an OutputBatch is open on a thread, AtomicOutput::commit() on
/// that thread checks and closes its temporary but leaves it in place; OutputBatch::commit() checks
/// every target again and only then renames every temporary over its target. Destroyed without
/// commit() (an error, a cancel), it removes the temporaries: no file of the set is replaced, so the
/// previous set stays whole. A batch opened inside another joins it (the outer one commits).
class OutputBatch {
 public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  /// Renames every finished temporary into place, after checking that each target is still absent
  /// or a regular file. Throws Error(Io) naming the target that cannot be replaced (then none is).
  void commit();

  /// The batch open on this thread, or null (AtomicOutput::commit()).
  static OutputBatch* current();
  /// Takes a finished temporary (registered in `slot` for removal on an interrupt) to rename at commit().
  void defer(std::filesystem::path temporary, std::filesystem::path target, int slot);

 private:
  struct Pending {
    std::filesystem::path temporary, target;
    int slot = -1;
  };
  std::vector<Pending> pending_;
  bool outermost_ = false;
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

/// Registers a child process (gnuplot) for removeTemporaryFilesNow() to stop; returns the slot for
/// unregisterChildProcess (-1 when all 16 slots are busy).
int registerChildProcess(pid_t pid) noexcept;
void unregisterChildProcess(int slot) noexcept;

/// Stops every registered child process (SIGKILL), then removes every registered temporary file.
/// Async-signal-safe (kill and unlink only): the CLI calls it from its SIGINT/SIGTERM/SIGHUP handler.
void removeTemporaryFilesNow() noexcept;

/// The files a command reads and writes, checked before any work starts (check()):
///   - no output is an input, and no two outputs are the same file; paths are compared after
///     resolving "..", symlinks and hard links;
///   - with an output folder, every output lies inside it;
///   - every output can be written: it is absent or a regular file (not a folder, symbolic link,
///     device node, FIFO or socket), each name in its path fits the file system (NAME_MAX, usually
///     255 bytes) and the whole path PATH_MAX (4096 bytes), and its folder exists or can be created
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
