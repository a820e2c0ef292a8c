#include "gnuplot.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/fit/gnuplot.hpp>

#include <unistd.h>

namespace brdfbake::cli {
namespace fs = std::filesystem;

void checkChartPath(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".svg")
    throw Error(Error::Kind::InvalidArgument, output.string() + ": chart must be .png or .svg");
}

void renderWithGnuplot(const std::string& body, const fs::path& output) {
  renderWithGnuplot(std::vector{body}, output);
}

void renderWithGnuplot(const std::vector<std::string>& panels, const fs::path& output) {
  checkChartPath(output);
  if (!findGnuplot()) {
    throw Error(Error::Kind::Io,
                "gnuplot not found: install gnuplot-nox (Debian), or use --csv / --json for the points");
  }
  const std::string ext = output.extension().string();
  AtomicOutput file(output);
  const fs::path& temporary = file.temporaryPath();
  const std::string size = "size 900," + std::to_string(600 * std::max<std::size_t>(1, panels.size()));
  const std::string terminal =
      (ext == ".png" ? "set terminal pngcairo " : "set terminal svg ") + size + " noenhanced\n";
  std::string body = panels.size() == 1 ? panels.front() : "";
  if (panels.size() > 1) {
    body = "set multiplot layout " + std::to_string(panels.size()) + ",1\n";
    for (const auto& panel : panels) body += "reset\n" + panel + "\n";
    body += "unset multiplot\n";
  }
  try {
    runGnuplot(terminal + "set output " + gnuplotQuote(temporary.string()) + "\n" + body + "\nset output\n");
  } catch (const Error& e) {
    throw Error(Error::Kind::Io, output.string() + ": " + e.what());
  }
  file.commit();
}

}  // namespace brdfbake::cli
