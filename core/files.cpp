#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>

#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <fstream>
#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;

std::string shortenForMessage(std::string_view text, std::size_t limit) {
  if (text.size() <= limit) return std::string(text);
  const std::size_t half = limit / 2;
  return std::string(text.substr(0, half)) + "..." + std::string(text.substr(text.size() - half)) + " (" +
         std::to_string(text.size()) + " characters)";
}

namespace {
std::string named(const fs::path& path) { return shortenForMessage(path.string()); }
}  // namespace

std::uintmax_t requireInputFile(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(Error::Kind::Io, named(path) + ": no such file (" + what + ")");
  if (fs::is_directory(status)) throw Error(Error::Kind::Io, named(path) + ": is a folder, not a file (" + what + ")");
  if (!fs::is_regular_file(status)) throw Error(Error::Kind::Io, named(path) + ": not a regular file (" + what + ")");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(Error::Kind::Io, named(path) + ": cannot read: " + ec.message());
  return size;
}

std::string readTextFile(const fs::path& path, const std::string& what, std::uintmax_t maxBytes) {
  const std::uintmax_t size = requireInputFile(path, what);
  if (size > maxBytes) {
    throw Error(Error::Kind::Resource, named(path) + ": " + std::to_string(size) + " bytes, more than the " +
                                           std::to_string(maxBytes) + " bytes accepted for a " + what);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Error::Kind::Io, named(path) + ": cannot open (" + what + ")");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw Error(Error::Kind::Io, named(path) + ": read failed (" + what + ")");
  return std::move(buffer).str();
}

// ---- temporaries, removable from a signal handler ------------------------------------------------
namespace {

struct TemporarySlot {
  std::atomic<bool> used{false};
  char path[4096] = {};
};
std::array<TemporarySlot, 128> temporarySlots;

int registerTemporary(const fs::path& path) {
  const std::string text = fs::absolute(path).string();
  if (text.size() >= sizeof(TemporarySlot::path)) return -1;
  for (std::size_t i = 0; i < temporarySlots.size(); ++i) {
    TemporarySlot& slot = temporarySlots[i];
    if (slot.used.load()) continue;
    std::memcpy(slot.path, text.c_str(), text.size() + 1);
    bool expected = false;
    if (slot.used.compare_exchange_strong(expected, true)) return static_cast<int>(i);
  }
  return -1;  // all slots busy: the destructor still removes it, only an interrupt would not
}

void unregisterTemporary(int slot) {
  if (slot >= 0) temporarySlots[static_cast<std::size_t>(slot)].used.store(false);
}

fs::path temporarySibling(const fs::path& target) {
  static std::atomic<int> counter{0};
  // Short enough for any file system's name limit, with the extension kept for format detection.
  std::string stem = target.stem().string().substr(0, 64);
  return target.parent_path() / ("." + stem + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                                 target.extension().string());
}

}  // namespace

void removeTemporaryFilesNow() noexcept {
  for (auto& slot : temporarySlots) {
    if (slot.used.load()) ::unlink(slot.path);
  }
}

AtomicOutput::AtomicOutput(fs::path target) : target_(std::move(target)) {
  std::error_code ec;
  if (fs::is_directory(target_, ec)) {
    throw Error(Error::Kind::Io, named(target_) + ": is a folder; give an output file name");
  }
  const fs::path folder = target_.parent_path();
  if (!folder.empty()) {
    fs::create_directories(folder, ec);
    if (ec) throw Error(Error::Kind::Io, named(folder) + ": cannot create the output folder: " + ec.message());
  }
  temporary_ = temporarySibling(target_);
  slot_ = registerTemporary(temporary_);
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
  unregisterTemporary(slot_);
}

void AtomicOutput::commit() {
  std::error_code ec;
  if (!fs::exists(temporary_, ec)) throw Error(Error::Kind::Io, named(target_) + ": nothing was written");
  if (fs::is_directory(target_, ec))
    throw Error(Error::Kind::Io, named(target_) + ": is a folder; give an output file name");
  fs::rename(temporary_, target_, ec);
  if (ec) throw Error(Error::Kind::Io, named(target_) + ": cannot move the finished file into place: " + ec.message());
  committed_ = true;
  unregisterTemporary(slot_);
  slot_ = -1;
}

ScratchFile::ScratchFile(const std::string& suffix) {
  static std::atomic<int> counter{0};
  std::error_code ec;
  fs::path folder = fs::temp_directory_path(ec);
  if (ec) folder = "/tmp";
  path_ = folder / ("brdfbake-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + suffix);
  slot_ = registerTemporary(path_);
}

ScratchFile::~ScratchFile() {
  std::error_code ec;
  fs::remove(path_, ec);
  unregisterTemporary(slot_);
}

void writeFileAtomically(const fs::path& target, std::string_view bytes) {
  AtomicOutput output(target);
  {
    std::ofstream out(output.temporaryPath(), std::ios::binary);
    if (!out) throw Error(Error::Kind::Io, named(target) + ": cannot write (is the folder writable?)");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw Error(Error::Kind::Io, named(target) + ": write failed (disk full?)");
  }
  output.commit();
}

fs::path siblingWithSuffix(const fs::path& path, const std::string& suffix) {
  return path.parent_path() / (path.stem().string() + suffix + path.extension().string());
}

// ---- planned files -------------------------------------------------------------------------------

fs::path resolvedPath(const fs::path& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec) absolute = path;
  fs::path resolved = fs::weakly_canonical(absolute, ec);
  return (ec ? absolute.lexically_normal() : resolved);
}

bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec)) return true;
  return resolvedPath(a) == resolvedPath(b);
}

namespace {

bool isInside(const fs::path& file, const fs::path& folder) {
  const fs::path relative = file.lexically_relative(folder);
  if (relative.empty()) return false;
  const std::string first = relative.begin()->string();
  return first != ".." && first != "." && !relative.is_absolute();
}

// The nearest existing ancestor must be a writable folder.
void requireWritableLocation(const fs::path& output, const std::string& role) {
  std::error_code ec;
  if (fs::is_directory(output, ec)) {
    throw Error(Error::Kind::InvalidArgument, role + ": " + named(output) + " is a folder; give an output file name");
  }
  fs::path ancestor = resolvedPath(output).parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, ec)) {
    if (ancestor == ancestor.parent_path()) break;
    ancestor = ancestor.parent_path();
  }
  if (!fs::is_directory(ancestor, ec)) {
    throw Error(Error::Kind::InvalidArgument,
                role + ": cannot write " + named(output) + ": " + named(ancestor) + " is not a folder");
  }
  if (::access(ancestor.c_str(), W_OK) != 0) {
    throw Error(Error::Kind::Io,
                role + ": cannot write " + named(output) + ": folder " + named(ancestor) + " is not writable");
  }
}

}  // namespace

FilePlan::FilePlan(std::optional<fs::path> outputFolder) : outputFolder_(std::move(outputFolder)) {}

void FilePlan::addInput(const fs::path& file, std::string role) { inputs_.push_back({file, std::move(role)}); }
void FilePlan::addOutput(const fs::path& file, std::string role) { outputs_.push_back({file, std::move(role)}); }

void FilePlan::check() const {
  // Each path is resolved once; hard links (the same file under two resolved names) are caught by
  // comparing inodes where both files exist.
  struct Resolved {
    const Entry* entry;
    fs::path path;
    bool exists;
  };
  auto resolveAll = [](const std::vector<Entry>& entries) {
    std::vector<Resolved> out;
    std::error_code ec;
    for (const Entry& e : entries) out.push_back({&e, resolvedPath(e.file), fs::exists(e.file, ec)});
    return out;
  };
  auto same = [](const Resolved& a, const Resolved& b) {
    std::error_code ec;
    return a.path == b.path || (a.exists && b.exists && fs::equivalent(a.entry->file, b.entry->file, ec));
  };
  const std::vector<Resolved> inputs = resolveAll(inputs_), outputs = resolveAll(outputs_);
  const std::optional<fs::path> folder = outputFolder_ ? std::optional(resolvedPath(*outputFolder_)) : std::nullopt;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const Entry& out = *outputs[i].entry;
    if (folder && !isInside(outputs[i].path, *folder)) {
      throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " lies outside the output folder " +
                                                    named(*outputFolder_) + "; outputs stay inside it");
    }
    for (const Resolved& in : inputs) {
      if (same(outputs[i], in)) {
        throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " is the " + in.entry->role +
                                                      " (an input); choose another output so no input is overwritten");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (same(outputs[i], outputs[j])) {
        throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " is also written as " +
                                                      outputs[j].entry->role + "; give each output its own file");
      }
    }
    requireWritableLocation(out.file, out.role);
  }
}

}  // namespace brdfbake
