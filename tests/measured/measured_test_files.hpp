#pragma once
// Helpers for the measured-table tests: writing small files and checking reader errors.
#include <brdfbake/core/error.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace brdfbake::test {

inline void writeFile(const std::filesystem::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
}

/// Success when `action` throws brdfbake::Error of `kind` whose message contains every fragment.
inline ::testing::AssertionResult throwsError(const std::function<void()>& action, Error::Kind kind,
                                              const std::vector<std::string>& fragments) {
  try {
    action();
  } catch (const Error& e) {
    const std::string message = e.what();
    if (e.kind() != kind) return ::testing::AssertionFailure() << "wrong kind of error: " << message;
    for (const std::string& fragment : fragments)
      if (message.find(fragment) == std::string::npos)
        return ::testing::AssertionFailure() << "message lacks '" << fragment << "': " << message;
    return ::testing::AssertionSuccess() << message;
  }
  return ::testing::AssertionFailure() << "no error thrown";
}

/// throwsError(action, InvalidInput, fragments).
inline ::testing::AssertionResult rejects(const std::function<void()>& action,
                                          const std::vector<std::string>& fragments) {
  return throwsError(action, Error::Kind::InvalidInput, fragments);
}

}  // namespace brdfbake::test
