#pragma once
/// @file
/// Parsing an enumeration from its name: every parse* function of the library throws the same
/// way (Error(InvalidArgument) listing the accepted names) instead of returning std::optional.

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// The candidate closest to `word` by edit distance, when close enough to be a typo (at most 2
/// edits, or a third of the word) or when `word` is the start of exactly one candidate: what a
/// "did you mean" names, for names of values, JSON keys, commands and flags.
std::optional<std::string> closestName(std::string_view word, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" for closestName(word, candidates), else "".
std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates);

/// The value among `values` whose name, toString(value) (found by argument-dependent lookup), is
/// `name`. Throws Error(InvalidArgument): "<what> must be one of a, b, c; got "x" (did you mean 'y'?)".
template <class Enum, std::size_t N>
Enum parseByName(std::string_view name, const std::array<Enum, N>& values, std::string_view what) {
  std::string accepted;
  std::vector<std::string> names;
  for (const Enum value : values) {
    if (name == toString(value)) return value;
    names.emplace_back(toString(value));
    accepted += (accepted.empty() ? "" : ", ") + names.back();
  }
  throw Error(Error::Kind::InvalidArgument, std::string(what) + " must be one of " + accepted + "; got \"" +
                                                printable(name, 40) + "\"" + didYouMean(name, names));
}

}  // namespace brdfbake
