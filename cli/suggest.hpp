#pragma once
// Errors of the flag parser, with the command or flag a mistyped one was probably meant to be.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace brdfbake::cli {

/// Prints CLI11's message for `error` (untrusted text made printable and shortened), with "did you
/// mean" for each unknown command or flag on the command line, and where to find the flags.
void reportParseError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv);

}  // namespace brdfbake::cli
