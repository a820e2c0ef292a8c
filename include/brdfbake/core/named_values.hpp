#pragma once
/// @file
/// Parsing an enumeration from its name: every parse* function of the library throws the same
/// way (Error(InvalidArgument) listing the accepted names) instead of returning std::optional.

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>

#include <array>
#include <string>
#include <string_view>

namespace brdfbake {

/// The value among `values` whose name, toString(value) (found by argument-dependent lookup), is
/// `name`. Throws Error(InvalidArgument): "<what> must be one of a, b, c; got "x"".
template <class Enum, std::size_t N>
Enum parseByName(std::string_view name, const std::array<Enum, N>& values, std::string_view what) {
  std::string accepted;
  for (const Enum value : values) {
    if (name == toString(value)) return value;
    accepted += (accepted.empty() ? "" : ", ") + std::string(toString(value));
  }
  throw Error(Error::Kind::InvalidArgument,
              std::string(what) + " must be one of " + accepted + "; got \"" + printable(name, 40) + "\"");
}

}  // namespace brdfbake
