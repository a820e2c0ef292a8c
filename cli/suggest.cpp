#include "suggest.hpp"

#include <brdfbake/core/named_values.hpp>
#include <brdfbake/io/files.hpp>

#include <algorithm>

#include "flags.hpp"

namespace brdfbake::cli {

namespace {

std::vector<std::string> commandNames(CLI::App& app) {
  std::vector<std::string> names;
  for (const auto* command : app.get_subcommands({})) names.push_back(command->get_name());
  return names;
}

std::vector<std::string> flagNames(const CLI::App& command) {
  std::vector<std::string> names;
  for (const auto* option : command.get_options()) {
    if (option->get_group().empty()) continue;  // hidden aliases are not suggested
    for (const auto& name : option->get_lnames()) names.push_back("--" + name);
    for (const auto& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

CLI::App* chosenCommand(CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    for (auto* command : app.get_subcommands({})) {
      if (command->get_name() == argv[i]) return command;
    }
  }
  return nullptr;
}

// What is wrong when no command was named: the first word is no command, or no flag of brdfbake
// itself (CLI11 says only "A subcommand is required" for both).
std::string noCommandMessage(CLI::App& app, const std::string& first) {
  const std::string word = "'" + shortenForMessage(first, 40) + "'";
  if (first.empty() || first[0] == '-') {
    return word + " is not a flag of brdfbake itself (--help, --version); a command comes first";
  }
  std::string names;
  for (const auto& name : commandNames(app)) names += (names.empty() ? "" : ", ") + name;
  std::string text = word + " is not a command (" + names + ")";
  if (const auto name = closestName(first, commandNames(app))) text += "; did you mean '" + *name + "'?";
  return text;
}

// "did you mean" lines for the command line's unknown flags.
std::vector<std::string> suggestions(CLI::App* command, int argc, char** argv) {
  std::vector<std::string> lines;
  if (!command) return lines;
  const std::vector<std::string> known = flagNames(*command);
  for (int i = 2; i < argc; ++i) {
    std::string word = argv[i];
    if (word.size() < 2 || word[0] != '-' || word == "--") continue;
    word = word.substr(0, word.find('='));
    if (std::find(known.begin(), known.end(), word) != known.end()) continue;
    if (const auto name = closestName(word, known)) {
      lines.push_back("'" + shortenForMessage(word, 40) + "' is not a flag of '" + command->get_name() +
                      "'; did you mean '" + *name + "'?");
    }
  }
  return lines;
}

}  // namespace

void reportParseError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  CLI::App* command = chosenCommand(app, argc, argv);
  const std::string what = !command && argc > 1 ? noCommandMessage(app, argv[1]) : shortenForMessage(error.what(), 300);
  std::string text = "brdfbake: error: " + what + "\n";
  for (const auto& line : suggestions(command, argc, argv)) text += "  " + line + "\n";
  text += "Run 'brdfbake " + (command ? command->get_name() + " " : std::string()) + "--help' for " +
          (command ? "its flags" : "the commands") + ".\n";
  writeStderr(text);
}

}  // namespace brdfbake::cli
