#pragma once
// A full disk to write on: a tmpfs of a few hundred KB mounted on a fresh folder for one test (it
// needs CAP_SYS_ADMIN, e.g. root in a container that allows mounts), unmounted when the test ends.
// Tests skip with a message where mounting is impossible. Nothing else of the machine is touched.
#include <sys/mount.h>
#include <sys/statvfs.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace brdfbake::test {

class TinyFilesystem {
 public:
  explicit TinyFilesystem(const std::string& size = "200k") {
    mountPoint_ = folder_ / "tiny";
    std::filesystem::create_directories(mountPoint_);
    const std::string options = "size=" + size + ",mode=0755";
    if (::mount("tmpfs", mountPoint_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV | MS_NOEXEC, options.c_str()) == 0) {
      mounted_ = true;
    } else {
      reason_ = std::string("cannot mount a tmpfs (") + std::strerror(errno) + "; needs CAP_SYS_ADMIN)";
    }
  }
  ~TinyFilesystem() {
    if (mounted_) ::umount2(mountPoint_.c_str(), MNT_DETACH);
  }
  TinyFilesystem(const TinyFilesystem&) = delete;
  TinyFilesystem& operator=(const TinyFilesystem&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& reason() const { return reason_; }
  const std::filesystem::path& path() const { return mountPoint_; }
  std::filesystem::path operator/(const std::string& name) const { return mountPoint_ / name; }
  /// Bytes still free.
  unsigned long long freeBytes() const {
    struct statvfs info {};
    return ::statvfs(mountPoint_.c_str(), &info) == 0 ? info.f_bavail * info.f_frsize : 0;
  }

 private:
  TempDir folder_;
  std::filesystem::path mountPoint_;
  bool mounted_ = false;
  std::string reason_;
};

/// Declares `var`, a mounted TinyFilesystem, or skips the test saying why.
#define BRDFBAKE_REQUIRE_TINY_FILESYSTEM(var, size) \
  ::brdfbake::test::TinyFilesystem var(size);       \
  if (!var.mounted()) GTEST_SKIP() << (var).reason()

}  // namespace brdfbake::test
