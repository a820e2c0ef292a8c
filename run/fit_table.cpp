#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/fit_report.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

// " mirror", " Lafortune", " half-vector" or " mixed", for the report's title.
const char* lobeKindName(const LobeModel& model) {
  if (model.allAboutMirror()) return " mirror";
  bool half = false, other = false;
  for (const auto& lobe : model.channels[0].lobes) (lobe.halfVector ? half : other) = true;
  return half ? (other ? " mixed" : " half-vector") : " Lafortune";
}

// The table as fitted: as measured (spectral) or converted to RGB, with where it came from.
MeasuredTable fittedChannels(const FitTableOptions& options, const MeasuredTable& read, FitSource& source) {
  source.file = options.table.filename().string();  // its name: no folder of this machine in the file
  source.format = std::string(toString(read.format));
  source.samples = read.size();
  const std::string count = std::to_string(read.channelCount());
  if (options.spectral) {
    if (read.kind != ChannelKind::Spectral) {
      throw Error(Error::Kind::InvalidArgument, options.table.string() +
                                                    ": fitting every wavelength needs a spectral table; this one has " +
                                                    count + " non-spectral channel(s)");
    }
    source.channels = "spectral: " + count + " channels as measured";
    source.notes = read.notes;
    return read;
  }
  MeasuredTable table = read.toRgb(options.rgb);
  source.channels =
      read.kind != ChannelKind::Spectral
          ? "rgb: as stored in the file"
          : std::string("rgb: ") +
                (options.rgb == RgbMethod::Cie1931 ? "CIE 1931 / D65 to linear sRGB" : "single wavelengths") +
                " from " + count + " spectral channels";
  source.notes = table.notes;
  return table;
}

std::string reportTitle(const FitTableOptions& options, const FitResult& fit) {
  std::ostringstream title;
  title << options.table.filename().string() << ": ";
  if (fit.model.hasHalfDifference())
    title << "half-difference table";
  else
    title << fit.model.channels[0].lobes.size() << " " << toString(fit.model.elevation) << lobeKindName(fit.model)
          << " lobe(s)";
  if (const auto& h = fit.heldOut) {
    title.precision(2);
    title << std::fixed << "; held-out / Lambert: k-fold " << h->kfold.ratio() << "x, elevations";
    for (const auto& e : h->elevations) title << " " << std::lround(e.elevationDegrees) << ":" << e.ratio() << "x";
  }
  return title.str();
}

// The splits where one row holds half or more of the fit's squared error (HeldOutSplit::largestRowShare).
void describeLargestRows(std::ostream& out, const HeldOutReport& report) {
  std::vector<const HeldOutSplit*> splits{&report.kfold};
  for (const auto& e : report.elevations) splits.push_back(&e);
  for (const HeldOutSplit* split : splits) {
    if (!(split->largestRowShare >= 0.5)) continue;
    const SampleAngles& row = split->largestRow;
    out << std::fixed << std::setprecision(0) << "  " << split->name << ": one row holds "
        << 100.0 * split->largestRowShare << " % of the squared error and " << 100.0 * split->largestRowLambertShare
        << " % of Lambert's (theta_i " << std::setprecision(1) << degrees(row.thetaIn) << ", theta_s "
        << degrees(row.thetaOut) << " deg: " << split->largestRowMirrorOffset
        << " deg from the mirror direction); without it " << std::setprecision(2) << split->ratioWithoutLargestRow()
        << "x\n";
  }
}
}  // namespace

void FitTableOptions::validate() const {
  fit.validate();
  if (!report.empty() && !findGnuplot()) {
    throw Error(Error::Kind::InvalidArgument,
                "the report chart needs gnuplot, which was not found (Debian: apt-get install gnuplot-nox)");
  }
}

FitTableResult fitTable(const FitTableOptions& options, const Context& context) {
  options.validate();
  FilePlan plan;
  plan.addInput(options.table, "table");
  if (!options.output.empty()) plan.addOutput(options.output, "fit.json output");
  if (!options.report.empty()) plan.addOutput(options.report, "report");
  plan.check();

  const MeasuredTable read = readTableForFitting(options.table, options.format);
  FitTableResult result;
  result.table = options.table;
  result.samples = read.size();
  const MeasuredTable table = fittedChannels(options, read, result.file.source);
  result.notes = result.file.source.notes;
  result.file.fit = fitLobes(table, options.fit, context.task("fit " + options.table.filename().string()));
  if (!options.output.empty()) writeFitFile(options.output, result.file), result.files.push_back(options.output);
  if (!options.report.empty()) {
    writeFitReport(options.report, table, result.file.fit.model, reportTitle(options, result.file.fit));
    result.files.push_back(options.report);
  }
  return result;
}

std::string FitTableResult::briefReport() const {
  const FitResult& fit = file.fit;
  std::ostringstream out;
  out << table.string() << ": " << samples << " samples, " << file.source.channels << "\n" << fit.briefReport();
  out << std::fixed << std::setprecision(4) << "  in-sample log error " << fit.inSampleError << "\n";
  if (const auto& h = fit.heldOut) {
    out << std::setprecision(2) << "  held-out log error / Lambert: " << h->kfold.name << " " << h->kfold.ratio()
        << "x";
    for (const auto& e : h->elevations) out << ", " << e.name << " " << e.ratio() << "x";
    out << " (" << std::setprecision(1) << h->seconds << " s)\n";
    describeLargestRows(out, *h);
  }
  if (!fit.candidates.empty()) {
    out << "  models tried (held-out score = the worse of the k-fold and elevation ratios to Lambert; *: weights\n"
           "  refined as the kept fit's, otherwise linearised at the data as the shape search ranks them):\n";
    auto describe = [&](const ModelCandidate& c) {
      out << c.lobes << " " << toString(c.kind) << " " << toString(c.elevation)
          << (c.colorProfile == ColorProfile::None ? "" : " colour-profiled") << (c.refined ? "*" : "") << ", "
          << c.parameters << " parameters: " << std::setprecision(3) << c.heldOutScore << " (k-fold " << c.kfoldRatio
          << "x, elevations " << c.elevationRatio << "x, " << std::setprecision(1) << c.seconds << " s)";
    };
    for (const auto& c : fit.candidates) {
      out << "    ";
      describe(c);
      out << (c.chosen ? " chosen" : c.worseThanLambert() ? " dropped: worse than Lambert" : "") << "\n";
    }
    if (const ModelCandidate* radial = fit.bestRadiallySymmetric()) {
      out << "  best radially symmetric (prefilters an environment): ";
      describe(*radial);
      out << "\n";
    }
  }
  for (const auto& note : notes) out << "  note: " << note << "\n";
  for (const auto& f : files) out << "wrote " << f.string() << "\n";
  if (!fit.usable()) out << "warning: the fit is not usable (a solve failed); see the termination per channel\n";
  return out.str();
}

nlohmann::json FitTableResult::toJson() const {
  return {{"table", table.string()},
          {"samples", samples},
          {"channels", file.source.channels},
          {"seconds", file.fit.seconds},
          {"usable", file.fit.usable()},
          {"files", pathsToJson(files)},
          {"notes", notes},
          {"fit", fitFileToJson(file)}};
}

}  // namespace brdfbake
