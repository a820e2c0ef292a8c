#include "gnuplot.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/fit/gnuplot.hpp>

#include <unistd.h>

namespace brdfbake::cli {
namespace fs = std::filesystem;

void checkChartPath(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".svg") throw Error(Error::Kind::InvalidArgument, output.string() + ": chart must be .png or .svg");
}

void renderWithGnuplot(const std::string& body, const fs::path& output) {
  checkChartPath(output);
  if (!findGnuplot()) {
    throw Error(Error::Kind::Io, "gnuplot not found: install gnuplot-nox (Debian), or use --csv / --json for the points");
  }
  const std::string ext = output.extension().string();
  AtomicOutput file(output);
  const fs::path& temporary = file.temporaryPath();
  const std::string terminal = ext == ".png" ? "set terminal pngcairo size 900,600 noenhanced\n" : "set terminal svg size 900,600 noenhanced\n";
  try {
    runGnuplot(terminal + "set output " + gnuplotQuote(temporary.string()) + "\n" + body + "\nset output\n");
  } catch (const Error& e) {
    throw Error(Error::Kind::Io, output.string() + ": " + e.what());
  }
  file.commit();
}

}  // namespace brdfbake::cli
