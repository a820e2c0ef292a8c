// brdfbake: bake reflectance functions into environment-map textures.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/version.hpp>

#include <unistd.h>

#include <csignal>
#include <iostream>
#include <map>
#include <new>

#include "commands.hpp"

namespace {

constexpr const char* kFooter = R"(Exit status: 0 success; 2 bad flags, spec or input file (the message names the
file, line or JSON path), or an output that would overwrite an input or leave the output
folder; 3 a file could not be read or written; 4 the work needs more memory than the budget
(BRDFBAKE_MEMORY_LIMIT, default half the machine's memory); 130, 143, 129 interrupted by
SIGINT, SIGTERM, SIGHUP (temporary files removed); 1 anything else. Nothing is written when
a spec is invalid, outputs appear atomically (never half-written), and no input is ever
overwritten.

Examples:
  brdfbake bake data_samples/specs/phong_eye.json --out-dir out/
  brdfbake sample out/phong_eye.exr --dir 0,0,1
  brdfbake info out/phong_eye.exr --json
  brdfbake convert out/phong_paraboloid.exr --to cube -o out/phong_cube.exr

Conventions (frames, image orientation, texel centres): docs/conventions.md)";

int exitCodeFor(brdfbake::Error::Kind kind) {
  switch (kind) {
    case brdfbake::Error::Kind::InvalidArgument:
    case brdfbake::Error::Kind::InvalidInput:
      return 2;
    case brdfbake::Error::Kind::Io:
      return 3;
    case brdfbake::Error::Kind::Resource:
      return 4;
    case brdfbake::Error::Kind::Numerical:
      return 1;
  }
  return 1;
}

// SIGINT, SIGTERM, SIGHUP: remove the temporaries of outputs being written, say so in one line and
// exit 128 + signal. Only async-signal-safe calls here.
template <std::size_t N>
void writeToStderr(const char (&text)[N]) {
  [[maybe_unused]] const auto written = ::write(STDERR_FILENO, text, N - 1);
}

extern "C" void onInterrupt(int signal) {
  brdfbake::removeTemporaryFilesNow();
  switch (signal) {
    case SIGINT:
      writeToStderr("\nbrdfbake: interrupted (SIGINT); temporary files removed\n");
      break;
    case SIGTERM:
      writeToStderr("\nbrdfbake: terminated (SIGTERM); temporary files removed\n");
      break;
    default:
      writeToStderr("\nbrdfbake: hung up (SIGHUP); temporary files removed\n");
      break;
  }
  ::_exit(128 + signal);
}

void installInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"brdfbake " BRDFBAKE_VERSION_STRING
               ": bake reflectance functions (Phong, Blinn-Phong, ...) into sphere, dual-paraboloid,\n"
               "cube and lat-long environment maps, and inspect or convert the maps it writes."};
  app.footer(kFooter);
  app.set_version_flag("--version", BRDFBAKE_VERSION_STRING);
  app.require_subcommand(1);

  std::map<CLI::App*, brdfbake::cli::Command> commands;
  auto add = [&](brdfbake::cli::Command (*factory)(CLI::App&)) {
    const std::size_t before = app.get_subcommands({}).size();
    auto command = factory(app);
    commands[app.get_subcommands({})[before]] = std::move(command);
  };
  add(brdfbake::cli::addBakeCommand);
  add(brdfbake::cli::addSampleCommand);
  add(brdfbake::cli::addInfoCommand);
  add(brdfbake::cli::addConvertCommand);
  add(brdfbake::cli::addPrefilterCommand);
  add(brdfbake::cli::addFitCommand);
  add(brdfbake::cli::addEvalCommand);
  add(brdfbake::cli::addPreviewCommand);
  add(brdfbake::cli::addChartCommand);
  add(brdfbake::cli::addInterpolationCommand);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  installInterruptHandlers();
  try {
    for (auto& [subcommand, run] : commands) {
      if (subcommand->parsed()) return run();
    }
  } catch (const brdfbake::Error& e) {
    std::cerr << "brdfbake: error: " << e.what() << "\n";
    return exitCodeFor(e.kind());
  } catch (const std::bad_alloc&) {
    std::cerr << "brdfbake: error: out of memory (lower the resolution, or set BRDFBAKE_MEMORY_LIMIT)\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "brdfbake: internal error: " << e.what() << "\n";
    return 1;
  }
  return 1;
}
