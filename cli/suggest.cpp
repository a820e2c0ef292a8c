#include "suggest.hpp"

#include <brdfbake/io/files.hpp>

#include <algorithm>

#include "flags.hpp"

namespace brdfbake::cli {

namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

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

// "did you mean" lines for the command line's unknown command or flags.
std::vector<std::string> suggestions(CLI::App& app, CLI::App* command, int argc, char** argv) {
  std::vector<std::string> lines;
  if (!command && argc > 1 && argv[1][0] != '-') {
    if (const auto name = closestName(argv[1], commandNames(app))) {
      lines.push_back("'" + shortenForMessage(argv[1], 40) + "' is not a command; did you mean '" + *name + "'?");
    }
    return lines;
  }
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

std::optional<std::string> closestName(const std::string& word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t bestDistance = std::max<std::size_t>(2, word.size() / 3) + 1;
  std::vector<std::string> extending;
  for (const auto& candidate : candidates) {
    if (candidate.rfind(word, 0) == 0) extending.push_back(candidate);
    const std::size_t distance = editDistance(word, candidate);
    if (distance < bestDistance) bestDistance = distance, best = candidate;
  }
  if (!best && extending.size() == 1) best = extending.front();
  return best;
}

void reportParseError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  CLI::App* command = chosenCommand(app, argc, argv);
  std::string text = "brdfbake: error: " + shortenForMessage(error.what(), 300) + "\n";
  for (const auto& line : suggestions(app, command, argc, argv)) text += "  " + line + "\n";
  text += "Run 'brdfbake " + (command ? command->get_name() + " " : std::string()) + "--help' for " +
          (command ? "its flags" : "the commands") + ".\n";
  writeStderr(text);
}

}  // namespace brdfbake::cli
