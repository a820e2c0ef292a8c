#include "commands.hpp"

namespace brdfbake::cli {

std::map<CLI::App*, Command> addCommands(CLI::App& app) {
  std::map<CLI::App*, Command> commands;
  for (auto factory :
       {addBakeCommand, addSampleCommand, addInfoCommand, addConvertCommand, addPrefilterCommand, addIblCommand,
        addMatcapCommand, addFitCommand, addEvalCommand, addPreviewCommand, addChartCommand, addInterpolationCommand}) {
    const std::size_t before = app.get_subcommands({}).size();
    Command command = factory(app);
    commands[app.get_subcommands({})[before]] = std::move(command);
  }
  return commands;
}

}  // namespace brdfbake::cli
