#pragma once
/// @file
/// Numbers written as text (a flag's value, a field of a table or a lobe's parameter), read whole:
/// one implementation for every reader, so "1e3" and " 2" mean the same everywhere and "1x",
/// "nan" and "inf" are refused everywhere.

#include <optional>
#include <string_view>

namespace brdfbake {

/// All of `text` (surrounding spaces and tabs and a leading '+' allowed) as a finite number, else
/// nullopt (empty, trailing characters, out of range, nan, inf).
std::optional<double> finiteNumberIn(std::string_view text);
/// All of `text` (as finiteNumberIn) as a whole number in int's range, else nullopt.
std::optional<int> wholeNumberIn(std::string_view text);

/// finiteNumberIn(text), or throws Error(InvalidArgument) "expected a finite number, got 'TEXT'".
double parseFiniteNumber(std::string_view text);
/// wholeNumberIn(text), or throws Error(InvalidArgument) "expected a whole number, got 'TEXT'".
int parseWholeNumber(std::string_view text);

}  // namespace brdfbake
