// Finds the image backend (image_backend.hpp): the module beside libbrdfbake_io, loaded once on
// first use, or the linked-in table of a static build.
#include "image_backend.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>

#ifdef BRDFBAKE_IMAGE_MODULE
#include <dlfcn.h>

#include <filesystem>
#endif

namespace brdfbake::image_backend {

#ifdef BRDFBAKE_IMAGE_MODULE
namespace {
namespace fs = std::filesystem;

const int kAnchor = 0;  // an object of libbrdfbake_io, to ask the dynamic loader where it is

// BRDFBAKE_IMAGE_MODULE (the module's file name) in the folder of libbrdfbake_io as loaded, which
// is where the build tree and `cmake --install` both put it; else in the folder of the library's
// real file, should the library be reached through a symbolic link from elsewhere.
fs::path modulePath() {
  Dl_info info{};
  if (dladdr(&kAnchor, &info) == 0 || info.dli_fname == nullptr) {
    throw Error(Error::Kind::Io,
                std::string("cannot locate libbrdfbake_io to find the image module ") + BRDFBAKE_IMAGE_MODULE);
  }
  const fs::path library(info.dli_fname);
  const fs::path beside = library.parent_path() / BRDFBAKE_IMAGE_MODULE;
  std::error_code ec;
  if (fs::exists(beside, ec)) return beside;
  const fs::path real = fs::canonical(library, ec);
  if (!ec && fs::exists(real.parent_path() / BRDFBAKE_IMAGE_MODULE, ec))
    return real.parent_path() / BRDFBAKE_IMAGE_MODULE;
  return beside;  // dlopen's message says it is missing
}

[[noreturn]] void failLoading(const fs::path& path, const std::string& why) {
  throw Error(Error::Kind::Io, "cannot load the image module " + path.string() +
                                   " (needed to read or write images; install it beside libbrdfbake_io): " + why);
}

// Never unloaded: OpenImageIO keeps threads and static state until exit. RTLD_LAZY leaves OpenImageIO's
// dependencies to bind as they would at start-up; the module itself is linked with -z now, so its own
// unresolved symbols still fail here, with dlerror's message.
const Functions& loadModule() {
  const fs::path path = modulePath();
  void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (handle == nullptr) failLoading(path, dlerror());
  using Factory = const Functions* (*)();
  const auto factory = reinterpret_cast<Factory>(dlsym(handle, "brdfbake_image_oiio_functions"));
  if (factory == nullptr) failLoading(path, dlerror());
  const Functions* functions = factory();
  if (functions == nullptr || functions->interfaceVersion != kInterfaceVersion ||
      std::string(functions->brdfbakeVersion) != BRDFBAKE_VERSION_STRING) {
    failLoading(path,
                "it is from another brdfbake build (interface " +
                    (functions ? std::to_string(functions->interfaceVersion) + ", version " + functions->brdfbakeVersion
                               : std::string("unknown")) +
                    "; this library: interface " + std::to_string(kInterfaceVersion) + ", version " +
                    BRDFBAKE_VERSION_STRING + ")");
  }
  return *functions;
}

}  // namespace

const Functions& imageBackend() {
  static const Functions& functions = loadModule();  // thread-safe; retried if it threw
  return functions;
}

#else

const Functions& imageBackend() { return *brdfbake_image_oiio_functions(); }

#endif

}  // namespace brdfbake::image_backend
