#include "gnuplot.hpp"

#include <brdfbake/core/error.hpp>

#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace brdfbake::cli {
namespace fs = std::filesystem;

void checkChartPath(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".svg") throw Error(Error::Kind::InvalidArgument, output.string() + ": chart must be .png or .svg");
}

void renderWithGnuplot(const std::string& body, const fs::path& output) {
  checkChartPath(output);
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    throw Error(Error::Kind::Io, "gnuplot not found: install gnuplot-nox (Debian), or use --csv / --json for the points");
  }
  const std::string ext = output.extension().string();
  const fs::path temporary = output.parent_path() / ("." + output.stem().string() + ".tmp-" + std::to_string(::getpid()) + ext);
  const fs::path script = fs::temp_directory_path() / ("brdfbake-" + std::to_string(::getpid()) + ".gp");
  {
    std::ofstream gp(script);
    gp << (ext == ".png" ? "set terminal pngcairo size 900,600 noenhanced\n" : "set terminal svg size 900,600 noenhanced\n");
    gp << "set output '" << temporary.string() << "'\n" << body << "\n";
  }
  const int status = std::system(("gnuplot '" + script.string() + "' 2>&1").c_str());
  std::error_code ec;
  fs::remove(script, ec);
  if (status != 0 || !fs::exists(temporary)) {
    fs::remove(temporary, ec);
    throw Error(Error::Kind::Io, output.string() + ": gnuplot failed");
  }
  fs::rename(temporary, output, ec);
  if (ec) throw Error(Error::Kind::Io, output.string() + ": " + ec.message());
}

}  // namespace brdfbake::cli
