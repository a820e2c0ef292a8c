#pragma once
// The subcommands of `brdfbake`. Each registers its options and returns the function that runs it.
#include <CLI/CLI.hpp>

#include <functional>

namespace brdfbake::cli {

using Command = std::function<int()>;  // returns the exit code; throws brdfbake::Error

Command addBakeCommand(CLI::App& app);
Command addSampleCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);
Command addPreviewCommand(CLI::App& app);
Command addChartCommand(CLI::App& app);
Command addInterpolationCommand(CLI::App& app);

}  // namespace brdfbake::cli
