// brdfbake: bake reflectance functions into environment-map textures. The commands parse their
// flags and call one library job each (include/brdfbake/run/); this file maps errors and signals to
// exit statuses and suggests the command or flag a mistyped one was meant to be.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/files.hpp>

#include <unistd.h>

#include <csignal>
#include <map>
#include <new>

#include "commands.hpp"
#include "flags.hpp"
#include "suggest.hpp"

namespace {

constexpr const char* kFooter = R"(Exit status: 0 success; 2 bad flags, spec or input file (the message names the
file, line or JSON path), or an output that would overwrite an input or leave the output
folder; 3 a file could not be read or written; 4 the work needs more memory than the budget
(BRDFBAKE_MEMORY_LIMIT, default half the machine's memory); 130, 143, 129 interrupted by
SIGINT, SIGTERM, SIGHUP (temporary files removed); 1 anything else. Nothing is written when
a spec is invalid, outputs appear atomically (never half-written), and no input is ever
overwritten. Progress goes to stderr (a bar on a terminal, plain lines otherwise).

Examples:
  brdfbake bake data_samples/specs/phong_eye.json --out-dir out/
  brdfbake sample out/phong_eye.exr --dir 0,0,1
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe ggx:0.3 --to cube -o out/sky.exr
  brdfbake fit table.astm -o fit.json

Every command explains itself: brdfbake COMMAND --help. Conventions (frames, image orientation,
texel centres, radiometric quantities): docs/conventions.md)";

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

int runCommand(const std::map<CLI::App*, brdfbake::cli::Command>& commands) {
  using brdfbake::writeStderr;
  try {
    for (const auto& [subcommand, run] : commands) {
      if (subcommand->parsed()) return run();
    }
  } catch (const brdfbake::Error& e) {
    writeStderr(std::string("brdfbake: error: ") + e.what() + "\n");
    return exitCodeFor(e.kind());
  } catch (const std::bad_alloc&) {
    writeStderr("brdfbake: error: out of memory (lower the resolution, or set BRDFBAKE_MEMORY_LIMIT)\n");
    return 4;
  } catch (const std::exception& e) {
    writeStderr(std::string("brdfbake: internal error: ") + e.what() + "\n");
    return 1;
  }
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"brdfbake " BRDFBAKE_VERSION_STRING
               ": bake reflectance functions (Phong, Cook-Torrance, measured tables and their fits, NPR\n"
               "maps) into sphere, dual-paraboloid, cube and lat-long maps, prefilter HDR environments, fit\n"
               "measured tables, and inspect, convert and preview what it writes."};
  app.footer(kFooter);
  app.set_version_flag("--version", BRDFBAKE_VERSION_STRING);
  app.require_subcommand(1);
  const std::map<CLI::App*, brdfbake::cli::Command> commands = brdfbake::cli::addCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    brdfbake::cli::reportParseError(app, e, argc, argv);
    return 2;
  }
  installInterruptHandlers();
  return runCommand(commands);
}
