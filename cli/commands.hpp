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
Command addPrefilterCommand(CLI::App& app);  // prefilter_command.cpp
Command addFitCommand(CLI::App& app);        // fit_command.cpp
Command addEvalCommand(CLI::App& app);       // eval_command.cpp
Command addPreviewCommand(CLI::App& app);
Command addChartCommand(CLI::App& app);
Command addInterpolationCommand(CLI::App& app);

}  // namespace brdfbake::cli
