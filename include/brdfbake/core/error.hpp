#pragma once
/// @file
/// The one exception type the library throws. The library never exits or prints; the CLI maps
/// `Error::Kind` to exit codes.

#include <brdfbake/core/printable.hpp>

#include <stdexcept>
#include <string>

namespace brdfbake {

class Error : public std::runtime_error {
 public:
  enum class Kind {
    InvalidArgument,  ///< a caller passed a value outside the documented range
    InvalidInput,     ///< a file or spec is malformed (message names file, line or JSON path)
    Io,               ///< a file could not be read or written
    Resource,         ///< the work would need more memory than allowed
    Numerical,        ///< a computation could not produce a finite result
  };

  Error(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

  Kind kind() const noexcept { return kind_; }

  /// Error(InvalidArgument) "<field>: <message>" for a field of a request, named in the request's own
  /// terms (snake_case, as spec keys and Python keywords spell it: "max_error"). field() gives it back,
  /// so that each front names it its own way once (the CLI by its flag, "--max-error").
  static Error invalidField(const std::string& field, const std::string& message) {
    Error error(Kind::InvalidArgument, field + ": " + message);
    error.field_ = field;
    return error;
  }
  /// The request field an invalidField error names ("" for other errors).
  const std::string& field() const noexcept { return field_; }
  /// The message without "<field>: " (what() for other errors).
  std::string problem() const { return field_.empty() ? what() : std::string(what()).substr(field_.size() + 2); }

  /// "<file>:<line>: <message>" (line omitted when 0); the file name goes through printable().
  static Error atFile(Kind kind, const std::string& file, int line, const std::string& message) {
    std::string where = printable(file);
    if (line > 0) {
      where += ':';
      where += std::to_string(line);
    }
    where += ": ";
    where += message;
    return Error(kind, where);
  }

 private:
  Kind kind_;
  std::string field_;
};

/// Throws Error::invalidField(field, message) unless `condition` holds.
inline void requireField(bool condition, const std::string& field, const std::string& message) {
  if (!condition) throw Error::invalidField(field, message);
}

/// Throws Error(InvalidArgument, message) unless `condition` holds.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(Error::Kind::InvalidArgument, message);
}

}  // namespace brdfbake
