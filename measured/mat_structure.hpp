#pragma once
// The structure of a MATLAB level-5 .mat file, checked before libmatio reads it (private to
// brdfbake_measured). libmatio 1.5.23 allocates what a file claims before it notices the file
// cannot hold it: a nested dimensions tag of 3.7 GB in a 480-byte file, 50000 x 50000 cells
// (20 GB of pointers, 129 s) in a 672-byte one. So every data element is walked here, compressed
// ones inflated (with zlib, bounded), and each claim is checked against the bytes that hold it.

#include <string>
#include <string_view>

namespace brdfbake::measured {

/// Deepest nesting of cells and structs accepted in a .mat file.
inline constexpr int kMaxMatNesting = 32;

/// Throws Error(InvalidInput) "<file>: ..." unless every data element of the level-5 file `bytes`
/// (its 128-byte header included) lies within its parent, and within each array (miMATRIX):
///   - the dimensions are non-negative, at most 32 of them;
///   - a numeric, logical or char array's data holds at least as many values as its dimensions;
///   - a cell array's cells, and a struct's fields times its elements, each need an 8-byte tag at
///     least, so they cannot outnumber an eighth of the array's bytes; each is walked in turn;
///   - cells and structs nest at most kMaxMatNesting levels.
/// A compressed element (miCOMPRESSED) is inflated (at most 1032 bytes per byte, within the memory
/// budget) and walked the same way. Truncated files fail here too.
void requireSaneMatStructure(std::string_view bytes, const std::string& file);

}  // namespace brdfbake::measured
