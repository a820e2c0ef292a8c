#include <brdfbake/core/error.hpp>
#include <brdfbake/io/files.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <climits>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <map>
#include <system_error>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {
std::string named(const fs::path& path) { return printable(path.string()); }
}  // namespace

std::string errnoText(int error) { return std::error_code(error, std::generic_category()).message(); }

void requireNoNul(const fs::path& path, const std::string& role) {
  if (path.native().find('\0') == std::string::npos) return;
  throw Error(Error::Kind::InvalidArgument,
              role + ": " + named(path) + ": contains a NUL character, which no file name may hold");
}

std::uintmax_t requireInputFile(const fs::path& path, const std::string& what) {
  requireNoNul(path, what);
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(Error::Kind::Io, named(path) + ": no such file (" + what + ")");
  if (fs::is_directory(status)) throw Error(Error::Kind::Io, named(path) + ": is a folder, not a file (" + what + ")");
  if (!fs::is_regular_file(status)) {
    throw Error(Error::Kind::Io,
                named(path) + ": is " + describeFileType(status.type()) + ", not a regular file (" + what + ")");
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(Error::Kind::Io, named(path) + ": cannot read: " + ec.message());
  return size;
}

InputFile::InputFile(const fs::path& path, const std::string& what) : path_(path), what_(what) {
  requireInputFile(path, what);  // the messages that name what is there instead
  // O_NONBLOCK: should a FIFO take the file's place after the check, opening it does not wait for a writer.
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd_ < 0) throw Error(Error::Kind::Io, named(path) + ": cannot open (" + what + "): " + errnoText(errno));
  struct stat opened {};
  if (::fstat(fd_, &opened) != 0 || !S_ISREG(opened.st_mode)) {
    ::close(fd_);
    throw Error(Error::Kind::Io, named(path) + ": not a regular file (" + what + ")");
  }
  size_ = static_cast<std::uintmax_t>(opened.st_size);
}

InputFile::~InputFile() { ::close(fd_); }

fs::path InputFile::openName() const {
  const fs::path name = "/proc/self/fd/" + std::to_string(fd_);
  return ::access(name.c_str(), R_OK) == 0 ? name : path_;
}

std::string InputFile::read(std::uintmax_t offset, std::size_t count) const {
  std::string bytes(count, '\0');
  std::size_t used = 0;
  while (used < count) {
    const ssize_t got = ::pread(fd_, bytes.data() + used, count - used, static_cast<off_t>(offset + used));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw Error(Error::Kind::Io, named(path_) + ": read failed (" + what_ + "): " + errnoText(errno));
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  bytes.resize(used);
  return bytes;
}

std::string readTextFile(const fs::path& path, const std::string& what, std::uintmax_t maxBytes) {
  const InputFile file(path, what);
  auto tooLarge = [&](std::uintmax_t bytes) {
    return Error(Error::Kind::Resource, named(path) + ": " + std::to_string(bytes) + " bytes or more, more than the " +
                                            std::to_string(maxBytes) + " bytes accepted for a " + what);
  };
  if (file.size() > maxBytes) throw tooLarge(file.size());
  // Read with a bound, whatever the size said: a file may grow while it is read. A read shorter than
  // asked is the end of the file.
  std::string bytes;
  for (std::uintmax_t ask = std::max<std::uintmax_t>(file.size(), 4096);; ask = bytes.size()) {
    ask = std::min<std::uintmax_t>(ask, maxBytes + 1 - bytes.size());
    const std::string part = file.read(bytes.size(), static_cast<std::size_t>(ask));
    bytes += part;
    if (bytes.size() > maxBytes) throw tooLarge(bytes.size());
    if (part.size() < ask) break;
  }
  return bytes;
}

// ---- temporaries and child processes, removable from a signal handler ----------------------------
namespace {

struct TemporarySlot {
  std::atomic<bool> used{false};
  char path[4096] = {};
};
std::array<TemporarySlot, 128> temporarySlots;
std::array<std::atomic<pid_t>, 16> childSlots{};

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
  // Short enough for any file system's name limit, with the extension kept for format detection;
  // only plain characters, so the name passes unchanged through a program's quoting (gnuplot's).
  auto plain = [](std::string text) {
    for (char& c : text)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
    return text;
  };
  const std::string stem = plain(target.stem().string().substr(0, 64));
  const std::string extension = plain(target.extension().string().substr(0, 16));
  return target.parent_path() /
         ("." + stem + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + extension);
}

}  // namespace

int registerChildProcess(pid_t pid) noexcept {
  for (std::size_t i = 0; i < childSlots.size(); ++i) {
    pid_t expected = 0;
    if (childSlots[i].compare_exchange_strong(expected, pid)) return static_cast<int>(i);
  }
  return -1;
}

void unregisterChildProcess(int slot) noexcept {
  if (slot >= 0) childSlots[static_cast<std::size_t>(slot)].store(0);
}

void removeTemporaryFilesNow() noexcept {
  // Children first, so none writes a temporary again after it is removed.
  for (auto& child : childSlots) {
    const pid_t pid = child.load();
    if (pid > 0) ::kill(pid, SIGKILL);
  }
  for (auto& slot : temporarySlots) {
    if (slot.used.load()) ::unlink(slot.path);
  }
}

std::string describeFileType(fs::file_type type) {
  switch (type) {
    case fs::file_type::regular:
      return "a regular file";
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::symlink:
      return "a symbolic link";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::fifo:
      return "a FIFO (named pipe)";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

void requireReplaceableOutput(const fs::path& path, Error::Kind kind, const std::string& role) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);  // never follows a link at the target
  if (!fs::exists(status) || fs::is_regular_file(status)) return;
  const std::string prefix = role.empty() ? "" : role + ": ";
  if (fs::is_directory(status)) throw Error(kind, prefix + named(path) + " is a folder; give an output file name");
  throw Error(kind, prefix + named(path) + " is " + describeFileType(status.type()) +
                        "; brdfbake replaces only regular files (remove it or choose another output)");
}

AtomicOutput::AtomicOutput(fs::path target) : target_(std::move(target)) {
  requireNoNul(target_, "output");
  requireReplaceableOutput(target_, Error::Kind::Io);
  std::error_code ec;
  const fs::path folder = target_.parent_path();
  if (!folder.empty()) {
    fs::create_directories(folder, ec);
    if (ec) throw Error(Error::Kind::Io, named(folder) + ": cannot create the output folder: " + ec.message());
  }
  temporary_ = temporarySibling(target_);
  slot_ = registerTemporary(temporary_);
}

AtomicOutput::~AtomicOutput() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
  unregisterTemporary(slot_);
}

int AtomicOutput::open() {
  if (fd_ >= 0) return fd_;
  require(!committed_, "AtomicOutput::open: already committed");
  fd_ = ::open(temporary_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd_ < 0) {
    throw Error(Error::Kind::Io, named(target_) + ": cannot create " + named(temporary_) + ": " + errnoText(errno));
  }
  return fd_;
}

void AtomicOutput::write(std::string_view bytes) {
  const int fd = open();
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd, bytes.data(), bytes.size());
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) throw writeFailed(written < 0 ? errno : ENOSPC);
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
}

void AtomicOutput::close() {
  if (fd_ < 0) return;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0 && errno != EINTR) throw writeFailed(errno);
}

Error AtomicOutput::writeFailed(int error) const {
  return Error(Error::Kind::Io, named(target_) + ": write failed: " + errnoText(error) +
                                    (error == ENOSPC || error == EDQUOT ? " (disk full)" : ""));
}

void AtomicOutput::commit() {
  close();
  std::error_code ec;
  const fs::file_status written = fs::symlink_status(temporary_, ec);
  if (!fs::exists(written)) throw Error(Error::Kind::Io, named(target_) + ": nothing was written");
  if (!fs::is_regular_file(written)) {
    throw Error(Error::Kind::Io, named(target_) + ": the temporary " + named(temporary_) + " is " +
                                     describeFileType(written.type()) + ", not the file written");
  }
  if (OutputBatch* batch = OutputBatch::current()) {  // renamed with the rest of the set
    batch->defer(temporary_, target_, slot_);
    committed_ = true;
    slot_ = -1;
    return;
  }
  requireReplaceableOutput(target_, Error::Kind::Io);  // again: something may have appeared meanwhile
  fs::rename(temporary_, target_, ec);
  if (ec) throw Error(Error::Kind::Io, named(target_) + ": cannot move the finished file into place: " + ec.message());
  committed_ = true;
  unregisterTemporary(slot_);
  slot_ = -1;
}

namespace {
thread_local OutputBatch* openBatch = nullptr;
}  // namespace

OutputBatch::OutputBatch() {
  if (!openBatch) openBatch = this, outermost_ = true;
}

OutputBatch::~OutputBatch() {
  if (!outermost_) return;
  openBatch = nullptr;
  for (const Pending& p : pending_) {
    std::error_code ec;
    fs::remove(p.temporary, ec);
    unregisterTemporary(p.slot);
  }
}

OutputBatch* OutputBatch::current() { return openBatch; }

void OutputBatch::defer(fs::path temporary, fs::path target, int slot) {
  pending_.push_back({std::move(temporary), std::move(target), slot});
}

void OutputBatch::commit() {
  if (!outermost_) return;
  openBatch = nullptr;  // from here on, commits are this batch's own renames
  for (const Pending& p : pending_) requireReplaceableOutput(p.target, Error::Kind::Io);
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    std::error_code ec;
    fs::rename(pending_[i].temporary, pending_[i].target, ec);
    if (ec) {
      throw Error(Error::Kind::Io,
                  named(pending_[i].target) + ": cannot move the finished file into place: " + ec.message());
    }
    unregisterTemporary(pending_[i].slot);
    pending_[i].slot = -1;
    pending_[i].temporary.clear();
  }
  pending_.clear();
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
  output.write(bytes);
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
// Each name in `path` within the file system's limit (NAME_MAX of the folder that will hold it,
// usually 255 bytes), the whole path within PATH_MAX (4096 bytes).
void requireNameLengths(const fs::path& output, const fs::path& existingFolder, const std::string& role) {
  const std::string whole = fs::absolute(output).string();
  if (whole.size() >= PATH_MAX) {
    throw Error(Error::Kind::InvalidArgument, role + ": " + named(output) + ": a path of " +
                                                  std::to_string(whole.size()) + " bytes; the system's limit is " +
                                                  std::to_string(PATH_MAX - 1) + " (PATH_MAX)");
  }
  const long limit = ::pathconf(existingFolder.c_str(), _PC_NAME_MAX);
  const std::size_t nameMax = limit > 0 ? static_cast<std::size_t>(limit) : NAME_MAX;
  for (const fs::path& part : output) {
    if (part.string().size() > nameMax) {
      throw Error(Error::Kind::InvalidArgument,
                  role + ": " + named(output) + ": the name " + printable(part.string(), 60) + " has " +
                      std::to_string(part.string().size()) + " bytes; the file system's limit is " +
                      std::to_string(nameMax) + " (NAME_MAX)");
    }
  }
}

void requireWritableLocation(const fs::path& output, const std::string& role) {
  std::error_code ec;
  requireReplaceableOutput(output, Error::Kind::InvalidArgument, role);
  fs::path ancestor = resolvedPath(output).parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, ec)) {
    if (ancestor == ancestor.parent_path()) break;
    ancestor = ancestor.parent_path();
  }
  if (!fs::is_directory(ancestor, ec)) {
    throw Error(Error::Kind::InvalidArgument,
                role + ": cannot write " + named(output) + ": " + named(ancestor) + " is not a folder");
  }
  requireNameLengths(output, ancestor, role);
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
  for (const auto* list : {&inputs_, &outputs_})
    for (const Entry& e : *list) requireNoNul(e.file, e.role);
  // Each path is resolved and stat'ed once, then looked up: linear in the number of files (a spec
  // of 1024 maps with their mip levels plans thousands). Hard links (the same file under two
  // resolved names) are caught by their inode where the file exists.
  struct Resolved {
    fs::path path;
    std::pair<dev_t, ino_t> inode{0, 0};  // 0, 0: the file does not exist yet
  };
  auto resolve = [](const Entry& e) {
    Resolved r{resolvedPath(e.file)};
    struct stat info {};
    if (::stat(e.file.c_str(), &info) == 0) r.inode = {info.st_dev, info.st_ino};
    return r;
  };
  std::map<fs::path, const Entry*> inputPaths, outputPaths;
  std::map<std::pair<dev_t, ino_t>, const Entry*> inputInodes, outputInodes;
  for (const Entry& e : inputs_) {
    const Resolved r = resolve(e);
    inputPaths.emplace(r.path, &e);
    if (r.inode.second != 0) inputInodes.emplace(r.inode, &e);
  }
  auto find = [](const auto& table, const auto& key) -> const Entry* {
    const auto it = table.find(key);
    return it == table.end() ? nullptr : it->second;
  };
  const std::optional<fs::path> folder = outputFolder_ ? std::optional(resolvedPath(*outputFolder_)) : std::nullopt;
  for (const Entry& out : outputs_) {
    const Resolved r = resolve(out);
    if (folder && !isInside(r.path, *folder)) {
      throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " lies outside the output folder " +
                                                    named(*outputFolder_) + "; outputs stay inside it");
    }
    const Entry* in = find(inputPaths, r.path);
    if (!in && r.inode.second != 0) in = find(inputInodes, r.inode);
    if (in) {
      throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " is the " + in->role +
                                                    " (an input); choose another output so no input is overwritten");
    }
    const Entry* earlier = find(outputPaths, r.path);
    if (!earlier && r.inode.second != 0) earlier = find(outputInodes, r.inode);
    if (earlier) {
      throw Error(Error::Kind::InvalidArgument, out.role + ": " + named(out.file) + " is also written as " +
                                                    earlier->role + "; give each output its own file");
    }
    outputPaths.emplace(r.path, &out);
    if (r.inode.second != 0) outputInodes.emplace(r.inode, &out);
    requireWritableLocation(out.file, out.role);
  }
}

}  // namespace brdfbake
