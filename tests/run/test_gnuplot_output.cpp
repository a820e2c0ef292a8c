// Charts through gnuplot (core/gnuplot.hpp; here beside the fit report that draws them): the script renderChart hands
// to gnuplot, read by a stand-in gnuplot that keeps it, and, when gnuplot is installed, the picture it draws decoded
// and its pixels checked where the script put known colours.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::GnuplotVariable;
using test::slurp;

TEST(Gnuplot, QuotesAndChartPaths) {
  EXPECT_EQ(gnuplotQuote("it's here"), "'it''s here'");
  EXPECT_EQ(gnuplotQuote("a\nb"), "'ab'");  // a line break would end the command
  EXPECT_NO_THROW(checkChartPath("chart.png"));
  EXPECT_NO_THROW(checkChartPath("dir/chart.svg"));
  EXPECT_THROW(checkChartPath("chart.jpg"), Error);
  EXPECT_THROW(checkChartPath("chart"), Error);
}

TEST(Gnuplot, TheScriptSetsTheTerminalTheOutputAndOnePanelPerBody) {
  // A stand-in gnuplot keeps the script it is given and writes the picture where the script's
  // "set output" says.
  test::TempDir dir;
  const fs::path standIn = dir / "gnuplot", kept = dir / "kept.gp";
  std::ofstream(standIn) << "#!/bin/sh\ncp \"$1\" '" << kept.string()
                         << "'\nout=$(sed -n \"s/^set output '\\(.*\\)'$/\\1/p\" \"$1\" | head -n 1)\n"
                            "if grep -q pngcairo \"$1\"; then printf '\\211PNG\\r\\n\\032\\npicture IEND\\256B`\\202'\n"
                            "else printf '<svg>picture</svg>\\n'; fi > \"$out\"\n";
  ::chmod(standIn.c_str(), 0755);
  const GnuplotVariable variable(standIn.string());
  renderChart(std::vector<std::string>{"plot x"}, dir / "one.png");
  EXPECT_NE(slurp(dir / "one.png").find("picture IEND"), std::string::npos);
  std::string script = slurp(kept);
  EXPECT_EQ(script.rfind("set terminal pngcairo size 900,600 noenhanced\nset output '", 0), 0u) << script;
  EXPECT_NE(script.find("\nplot x\n"), std::string::npos) << script;
  EXPECT_EQ(script.find("multiplot"), std::string::npos) << script;
  EXPECT_NE(script.find("\nset output\n"), std::string::npos) << script;

  renderChart(std::vector<std::string>{"plot x", "plot x*x", "plot 1"}, dir / "three.svg");
  script = slurp(kept);
  EXPECT_EQ(script.rfind("set terminal svg size 900,1800 noenhanced\n", 0), 0u) << script;
  const std::size_t layout = script.find("set multiplot layout 3,1\n"), first = script.find("reset\nplot x\n"),
                    second = script.find("reset\nplot x*x\n"), third = script.find("reset\nplot 1\n"),
                    end = script.find("unset multiplot\n");
  ASSERT_NE(layout, std::string::npos) << script;
  EXPECT_LT(layout, first);
  EXPECT_LT(first, second);
  EXPECT_LT(second, third);
  EXPECT_LT(third, end);
  EXPECT_EQ(end == std::string::npos, false);
  // The output is written whole or not at all: a gnuplot that fails leaves no picture.
  std::ofstream(dir / "failing") << "#!/bin/sh\necho 'line 1: undefined variable' >&2\nexit 1\n";
  ::chmod((dir / "failing").c_str(), 0755);
  const GnuplotVariable failing((dir / "failing").string());
  EXPECT_THROW(renderChart(std::vector<std::string>{"plot nothing"}, dir / "failed.png"), Error);
  EXPECT_FALSE(fs::exists(dir / "failed.png"));
}

TEST(Gnuplot, DrawsPanelsOf900By600PixelsWithTheirColoursWhereTheScriptPutsThem) {
  const GnuplotVariable variable(std::nullopt);
  if (!findGnuplot()) GTEST_SKIP() << "gnuplot not installed (Debian: gnuplot-nox); skipping";
  // Each panel fills the left half of its graph with one colour and plots nothing visible; pure
  // red, blue and white decode to the same values whatever the PNG's transfer curve.
  auto panel = [](const std::string& colour) {
    return "unset key\nset xrange [0:1]\nset yrange [0:1]\nset object 1 rect from graph 0, graph 0 to graph 0.5, "
           "graph 1 fc rgb '" +
           colour + "' fillstyle solid 1.0 noborder\nplot 2 notitle\n";
  };
  test::TempDir dir;
  renderChart(std::vector<std::string>{panel("#ff0000")}, dir / "one.png");
  const Image one = readImage(dir / "one.png");
  ASSERT_EQ(one.width(), 900);
  ASSERT_EQ(one.height(), 600);
  EXPECT_LT((one.at(250, 300).head<3>() - Rgb(1, 0, 0)).abs().maxCoeff(), 0.01) << one.at(250, 300).transpose();
  EXPECT_LT((one.at(700, 300).head<3>() - Rgb(1, 1, 1)).abs().maxCoeff(), 0.01) << one.at(700, 300).transpose();

  renderChart(std::vector<std::string>{panel("#ff0000"), panel("#0000ff")}, dir / "two.png");
  const Image two = readImage(dir / "two.png");
  ASSERT_EQ(two.width(), 900);
  ASSERT_EQ(two.height(), 1200);
  EXPECT_LT((two.at(250, 300).head<3>() - Rgb(1, 0, 0)).abs().maxCoeff(), 0.01) << two.at(250, 300).transpose();
  EXPECT_LT((two.at(250, 900).head<3>() - Rgb(0, 0, 1)).abs().maxCoeff(), 0.01) << two.at(250, 900).transpose();
  EXPECT_LT((two.at(700, 900).head<3>() - Rgb(1, 1, 1)).abs().maxCoeff(), 0.01) << two.at(700, 900).transpose();
}

}  // namespace
}  // namespace brdfbake
