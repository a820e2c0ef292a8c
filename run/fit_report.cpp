#include <brdfbake/core/error.hpp>
#include <brdfbake/run/fit_report.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace brdfbake {
namespace {

struct Plotted {
  std::size_t channel;
  const char* color;
};

std::vector<Plotted> plottedChannels(const MeasuredTable& table) {
  const char* colors[3] = {"#c0392b", "#27ae60", "#2e6fd0"};  // red, green, blue
  std::vector<Plotted> plotted;
  if (table.kind == ChannelKind::Spectral && !table.wavelengthsNm.empty()) {
    for (int i = 0; i < 3; ++i) {
      const double target = 650.0 - 100.0 * i;
      std::size_t best = 0;
      for (std::size_t c = 0; c < table.wavelengthsNm.size(); ++c) {
        if (std::abs(table.wavelengthsNm[c] - target) < std::abs(table.wavelengthsNm[best] - target)) best = c;
      }
      if (std::none_of(plotted.begin(), plotted.end(), [&](const Plotted& p) { return p.channel == best; })) {
        plotted.push_back({best, colors[i]});
      }
    }
    return plotted;
  }
  for (std::size_t c = 0; c < std::min<std::size_t>(3, table.channelCount()); ++c) {
    plotted.push_back({c, table.channelCount() == 1 ? "#333333" : colors[c]});
  }
  return plotted;
}

}  // namespace

std::string fitReportScript(const std::filesystem::path& png, const MeasuredTable& table, const LobeModel& model,
                            const std::string& title) {
  require(table.channelCount() == model.channelCount(),
          "fit report: the table has " + std::to_string(table.channelCount()) + " channels, the model " +
              std::to_string(model.channelCount()));
  const auto thetas = table.incidentThetas();
  require(!thetas.empty(), "fit report: the table has no samples");
  const auto plotted = plottedChannels(table);
  const int panels = static_cast<int>(thetas.size());
  const int columns = std::min(4, panels), rows = (panels + columns - 1) / columns;

  std::ostringstream s;
  s.precision(9);
  // Data blocks: measured points and model curves per panel and channel.
  for (int p = 0; p < panels; ++p) {
    const double thetaIn = thetas[static_cast<std::size_t>(p)];
    const Vec3 wi = directionFromAngles(thetaIn, 0.0);
    for (std::size_t k = 0; k < plotted.size(); ++k) {
      const std::size_t c = plotted[k].channel;
      s << "$m" << p << "_" << k << " << EOD\n";
      for (std::size_t i : table.samplesAtIncidentTheta(thetaIn)) {
        const auto& a = table.angles[i];
        const bool inPlane = std::abs(std::sin(a.phiOut)) < 1e-5 || a.thetaOut < 1e-9;
        const double v = table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c));
        if (!inPlane || !(v > 0.0)) continue;
        s << (std::cos(a.phiOut) < 0.0 ? 1.0 : -1.0) * degrees(a.thetaOut) << " " << v << "\n";
      }
      s << "EOD\n$f" << p << "_" << k << " << EOD\n";
      for (double x = -89.0; x <= 89.0 + 1e-9; x += 0.25) {
        const Vec3 wo = directionFromAngles(radians(std::abs(x)), x > 0.0 ? kPi : 0.0);
        s << x << " " << std::max(model.evaluate(c, wi, wo), 1e-5) << "\n";
      }
      s << "EOD\n";
    }
  }
  s << "set terminal pngcairo size " << 420 * columns << "," << 340 * rows + 40 << " font 'sans,9'\n";
  s << "set output " << gnuplotQuote(png.string()) << "\nset termoption noenhanced\n";
  s << "set logscale y\nset format y '%g'\nset grid\nset key top left font ',8'\nset xrange [-90:90]\n";
  s << "set xlabel 'theta_s (deg), + mirror side'\nset ylabel 'BRDF (1/sr)'\n";
  s << "set multiplot layout " << rows << "," << columns << " title " << gnuplotQuote(title) << "\n";
  for (int p = 0; p < panels; ++p) {
    const double thetaDeg = degrees(thetas[static_cast<std::size_t>(p)]);
    s << "set title " << gnuplotQuote("theta_i = " + std::to_string(static_cast<int>(std::lround(thetaDeg))) + " deg")
      << "\n";
    s << "unset arrow\nset arrow from " << thetaDeg << ", graph 0 to " << thetaDeg
      << ", graph 1 nohead dt 2 lc rgb '#888888'\n";
    s << "plot ";
    for (std::size_t k = 0; k < plotted.size(); ++k) {
      const std::string name = table.channelNames.at(plotted[k].channel);
      if (k) s << ", ";
      s << "$m" << p << "_" << k << " with points pt 7 ps 0.6 lc rgb '" << plotted[k].color << "' title "
        << gnuplotQuote(name + " measured") << ", $f" << p << "_" << k << " with lines lw 1.5 lc rgb '"
        << plotted[k].color << "' title " << gnuplotQuote(name + " fit");
    }
    s << "\n";
  }
  s << "unset multiplot\n";
  return s.str();
}

void writeFitReport(const std::filesystem::path& png, const MeasuredTable& table, const LobeModel& model,
                    const std::string& title) {
  renderGnuplotOutput(
      png, [&](const std::filesystem::path& temporary) { return fitReportScript(temporary, table, model, title); });
}

}  // namespace brdfbake
