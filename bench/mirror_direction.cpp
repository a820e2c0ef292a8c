// mirror_direction: Zimmons & Bastos 1999's measured reflectance map (Zimmons & Bastos 1999 section 8) made two ways
// for the shared Cornell tables, side by side: the strongest sample near the mirror direction (the strongest-sample
// way; 10 degree window, and the whole incident angle as Zimmons & Bastos 1999 literally did) and the fitted lobes
// evaluated exactly on the mirror direction. Prints a Markdown table (G channel) and draws
// docs/images/mirror_direction.png with gnuplot when present.
//
//   mirror_direction [--shared ../shared/data/cornell] [--chart PNG | --update-docs]
// (--update-docs: the tracked docs/images/mirror_direction.png; without either, no chart)
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/fit/mirror_direction.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <iomanip>
#include <iostream>
#include <sstream>

using namespace brdfbake;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  fs::path shared = "../shared/data/cornell";
  fs::path chart;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--shared" && i + 1 < argc)
      shared = argv[++i];
    else if (arg == "--chart" && i + 1 < argc)
      chart = argv[++i];
    else if (arg == "--update-docs")
      chart = "docs/images/mirror_direction.png";
    else {
      std::cerr << "usage: mirror_direction [--shared DIR] [--chart PNG | --update-docs]\n";
      return 2;
    }
  }
  if (!fs::is_directory(shared)) {
    std::cerr << "mirror_direction: " << shared.string() << " not found; pass --shared DIR\n";
    return 1;
  }
  const std::vector<std::string> names{"garnet_red.astm", "garnet_red_RGB.astm", "krylon_blue.astm",
                                       "krylon_blue_RGB.astm"};
  try {
    std::ostringstream data;
    data.precision(6);
    std::cout << "| table | theta_i | nearest sample: G (offset from mirror) | strongest, 10 deg window: G (offset) | "
                 "strongest anywhere: G (offset) | fitted lobes on the mirror: G | fit / strongest |\n";
    std::cout << "|---|---|---|---|---|---|---|\n";
    for (std::size_t t = 0; t < names.size(); ++t) {
      const MeasuredTable table = readTableForFitting(shared / names[t]).toRgb();
      const MirrorDirectionTable strongest = strongestNearMirrorTable(table, radians(10.0));
      const MirrorDirectionTable literal = strongestNearMirrorTable(table, kPi);
      const MirrorDirectionTable nearest = strongestNearMirrorTable(table, 1e-9);  // no sample that close: the nearest
      const FitResult fit = fitLobes(table);
      const MirrorDirectionTable fitted = fittedMirrorTable(fit.model, strongest.thetas);
      for (std::size_t r = 0; r < strongest.thetas.size(); ++r) {
        const auto i = static_cast<Eigen::Index>(r);
        std::cout << std::fixed << "| " << names[t] << " | " << std::setprecision(0) << degrees(strongest.thetas[r])
                  << " | " << std::setprecision(3) << nearest.values(i, 1) << " (" << std::setprecision(1)
                  << degrees(nearest.offsets(i, 1)) << " deg) | " << std::setprecision(3) << strongest.values(i, 1)
                  << " (" << std::setprecision(1) << degrees(strongest.offsets(i, 1)) << " deg) | "
                  << std::setprecision(3) << literal.values(i, 1) << " (" << std::setprecision(1)
                  << degrees(literal.offsets(i, 1)) << " deg) | " << std::setprecision(3) << fitted.values(i, 1)
                  << " | " << std::setprecision(2) << fitted.values(i, 1) / strongest.values(i, 1) << " |\n";
      }
      // Chart data: strongest-sample points (10 degree window), strongest anywhere, fitted curve over 0-85 degrees.
      for (int c = 0; c < 3; ++c) {
        data << "$s" << t << "_" << c << " << EOD\n";
        for (std::size_t r = 0; r < strongest.thetas.size(); ++r)
          data << degrees(strongest.thetas[r]) << " " << strongest.values(static_cast<Eigen::Index>(r), c) << "\n";
        data << "EOD\n$l" << t << "_" << c << " << EOD\n";
        for (std::size_t r = 0; r < strongest.thetas.size(); ++r)
          data << degrees(strongest.thetas[r]) << " " << literal.values(static_cast<Eigen::Index>(r), c) << "\n";
        data << "EOD\n$f" << t << "_" << c << " << EOD\n";
        for (double deg = 0.0; deg <= 85.0 + 1e-9; deg += 0.5)
          data << deg << " "
               << std::max(fit.model.mirrorValue(static_cast<std::size_t>(c), std::cos(radians(deg))), 1e-4) << "\n";
        data << "EOD\n";
      }
      std::cerr << names[t] << ": " << fit.briefReport();
    }
    if (chart.empty()) return 0;
    if (!findGnuplot()) {
      std::cerr << "mirror_direction: gnuplot not found; no chart written\n";
      return 0;
    }
    std::ostringstream script;
    script << data.str();
    script << "set terminal pngcairo size 1200,900 font 'sans,10'\nset output " << gnuplotQuote(chart.string()) << "\n";
    script << "set termoption noenhanced\nset grid\nset logscale y\nset format y '%g'\nset key top left font ',8'\n";
    script << "set xlabel 'theta (deg): incident angle = angle between normal and view'\nset ylabel 'BRDF on the "
              "mirror direction (1/sr)'\n";
    script << "set xrange [0:90]\nset multiplot layout 2,2 title 'Mirror-direction tables: strongest nearby sample vs "
              "fitted lobes on the exact mirror'\n";
    const char* colors[] = {"#c0392b", "#27ae60", "#2e6fd0"};
    const char* channels[] = {"R", "G", "B"};
    for (std::size_t t = 0; t < names.size(); ++t) {
      script << "set title " << gnuplotQuote(names[t]) << "\nplot ";
      for (int c = 0; c < 3; ++c) {
        if (c) script << ", ";
        script << "$f" << t << "_" << c << " with lines lw 1.5 lc rgb '" << colors[c] << "' title '" << channels[c]
               << " fit', "
               << "$s" << t << "_" << c << " with linespoints pt 6 ps 1.2 dt 2 lw 1 lc rgb '" << colors[c]
               << "' title '" << channels[c] << " strongest (10 deg)', $l" << t << "_" << c
               << " with points pt 2 ps 1 lc rgb '" << colors[c] << "' title '" << channels[c]
               << " strongest (anywhere)'";
      }
      script << "\n";
    }
    script << "unset multiplot\n";
    runGnuplot(script.str());
    std::cerr << "wrote " << chart.string() << "\n";
  } catch (const Error& e) {
    std::cerr << "mirror_direction: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
