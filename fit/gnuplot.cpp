#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/fit/gnuplot.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;

std::optional<fs::path> findGnuplot() {
  if (const char* forced = std::getenv("BRDFBAKE_GNUPLOT")) {
    if (*forced == '\0' || ::access(forced, X_OK) != 0) return std::nullopt;
    return fs::path(forced);
  }
  const char* path = std::getenv("PATH");
  std::stringstream folders(path ? path : "/usr/bin:/bin");
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) continue;
    const fs::path candidate = fs::path(folder) / "gnuplot";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

std::string gnuplotQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'')
      quoted += "''";
    else if (c != '\n')
      quoted += c;
  }
  return quoted + "'";
}

void runGnuplot(const std::string& script) {
  const auto gnuplot = findGnuplot();
  if (!gnuplot) {
    throw Error(Error::Kind::InvalidArgument,
                "gnuplot not found on PATH (Debian: apt-get install gnuplot-nox); charts need it");
  }
  // The script goes through a file (no pipe that could break if gnuplot stops early).
  const ScratchFile scriptScratch(".gp"), errorsScratch(".log");
  const fs::path& scriptFile = scriptScratch.path();
  const fs::path& errors = errorsScratch.path();
  {
    std::ofstream out(scriptFile, std::ios::binary);
    out << script;
    if (!out) throw Error(Error::Kind::Io, scriptFile.string() + ": cannot write the gnuplot script");
  }
  auto shellQuote = [](const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  const std::string command = shellQuote(gnuplot->string()) + " " + shellQuote(scriptFile.string()) +
                              " </dev/null >/dev/null 2>" + shellQuote(errors.string());
  const int status = std::system(command.c_str());
  std::ifstream log(errors);
  std::stringstream messages;
  messages << log.rdbuf();
  if (status != 0) {
    std::string text = messages.str();
    if (text.size() > 2000) text = text.substr(0, 2000) + "...";
    throw Error(Error::Kind::Io, "gnuplot failed (status " + std::to_string(status) + "): " + text);
  }
}

void checkChartPath(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".svg") {
    throw Error(Error::Kind::InvalidArgument, shortenForMessage(output.string()) + ": a chart must be .png or .svg");
  }
}

void renderChart(const std::vector<std::string>& panels, const fs::path& output) {
  checkChartPath(output);
  if (!findGnuplot()) {
    throw Error(Error::Kind::Io,
                "gnuplot not found: install gnuplot-nox (Debian), or use --csv / --json for the points");
  }
  AtomicOutput file(output);
  const std::string size = "size 900," + std::to_string(600 * std::max<std::size_t>(1, panels.size()));
  const std::string terminal =
      (output.extension() == ".png" ? "set terminal pngcairo " : "set terminal svg ") + size + " noenhanced\n";
  std::string body = panels.size() == 1 ? panels.front() : "";
  if (panels.size() > 1) {
    body = "set multiplot layout " + std::to_string(panels.size()) + ",1\n";
    for (const auto& panel : panels) body += "reset\n" + panel + "\n";
    body += "unset multiplot\n";
  }
  try {
    runGnuplot(terminal + "set output " + gnuplotQuote(file.temporaryPath().string()) + "\n" + body + "\nset output\n");
  } catch (const Error& e) {
    throw Error(Error::Kind::Io, shortenForMessage(output.string()) + ": " + e.what());
  }
  file.commit();
}

}  // namespace brdfbake
