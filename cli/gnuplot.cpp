#include "gnuplot.hpp"

#include <brdfbake/core/error.hpp>
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
  const fs::path temporary =
      output.parent_path() / std::string(".").append(output.stem().string()).append(".tmp-").append(std::to_string(::getpid())).append(ext);
  const std::string terminal = ext == ".png" ? "set terminal pngcairo size 900,600 noenhanced\n" : "set terminal svg size 900,600 noenhanced\n";
  std::error_code ec;
  try {
    runGnuplot(terminal + "set output " + gnuplotQuote(temporary.string()) + "\n" + body + "\nset output\n");
  } catch (const Error& e) {
    fs::remove(temporary, ec);
    throw Error(Error::Kind::Io, output.string() + ": " + e.what());
  }
  if (!fs::exists(temporary)) throw Error(Error::Kind::Io, output.string() + ": gnuplot wrote nothing");
  fs::rename(temporary, output, ec);
  if (ec) throw Error(Error::Kind::Io, output.string() + ": " + ec.message());
}

}  // namespace brdfbake::cli
