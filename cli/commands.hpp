#pragma once
// The commands of `brdfbake`. Each registers its flags and returns the function that runs it: parse
// the flags into a job's options, call the job (include/brdfbake/run/), print its result.
#include <CLI/CLI.hpp>

#include <functional>
#include <map>

namespace brdfbake::cli {

using Command = std::function<int()>;  // returns the exit status; throws brdfbake::Error

/// Registers every command on `app`.
std::map<CLI::App*, Command> addCommands(CLI::App& app);

Command addBakeCommand(CLI::App& app);
Command addPrefilterCommand(CLI::App& app);
Command addMatcapCommand(CLI::App& app);
Command addChartCommand(CLI::App& app);
Command addFitCommand(CLI::App& app);
Command addEvalCommand(CLI::App& app);
Command addSampleCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);
Command addPreviewCommand(CLI::App& app);
Command addInterpolationCommand(CLI::App& app);
Command addIblCommand(CLI::App& app);

}  // namespace brdfbake::cli
