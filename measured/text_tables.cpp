// Text formats: Cornell ASTM E1392 (.astm) and pbrt-v2 (.brdf).
#include <brdfbake/io/files.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include "measured_common.hpp"

#include <cctype>
#include <cmath>
#include <fstream>

namespace brdfbake {

using measured::malformed;

namespace {

// Rows are gathered as flat numbers and moved into the table at the end.
struct RowCollector {
  std::vector<SampleAngles> angles;
  std::vector<double> values;
  std::size_t channels = 0;

  void finish(MeasuredTable& table) {
    table.angles = std::move(angles);
    table.values = Eigen::Map<const TableValues>(values.data(), static_cast<Eigen::Index>(table.angles.size()),
                                                 static_cast<Eigen::Index>(channels));
  }
};

// Parses one sample row (4 angles + channels) already split into fields.
void parseRow(const std::vector<std::string_view>& fields, const std::string& file, int line, RowCollector& rows) {
  static constexpr const char* kAngleNames[4] = {"theta_i", "phi_i", "theta_s", "phi_s"};
  double angle[4];
  for (int k = 0; k < 4; ++k) angle[k] = measured::finiteField(fields[k], file, line, kAngleNames[k]);
  const SampleAngles a{angle[0], angle[1], angle[2], angle[3]};
  measured::checkAngles(a, file, line);
  rows.angles.push_back(a);
  for (std::size_t c = 0; c < rows.channels; ++c)
    rows.values.push_back(measured::finiteField(fields[4 + c], file, line, "field " + std::to_string(5 + c)));
}

std::string columnCountMessage(std::size_t expected, std::size_t found, const char* separator, bool cutOff) {
  std::string message = "expected " + std::to_string(expected) + " " + separator +
                        " fields (theta_i, phi_i, theta_s, phi_s and " + std::to_string(expected - 4) +
                        " channels), found " + std::to_string(found);
  if (cutOff) message += " (the file ends in the middle of this line: truncated?)";
  return message;
}

bool isHeaderKey(std::string_view key) {
  if (key.empty() || !std::isalpha(static_cast<unsigned char>(key.front()))) return false;
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

bool startsLikeNumber(std::string_view text) {
  if (text.empty()) return false;
  const char c = text.front();
  return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
}

// Channel kind and wavelengths from the channel names of a VARS line.
void classifyChannels(MeasuredTable& table, const std::string& file, int line) {
  const auto& names = table.channelNames;
  std::vector<double> wavelengths;
  for (const std::string& name : names)
    if (auto w = measured::wavelengthFromChannelName(name)) wavelengths.push_back(*w);
  if (wavelengths.size() == names.size()) {
    for (std::size_t c = 1; c < wavelengths.size(); ++c)
      if (!(wavelengths[c] > wavelengths[c - 1]))
        throw malformed(
            file, line,
            "wavelengths must increase: '" + printable(names[c - 1], 60) + "' then '" + printable(names[c], 60) + "'");
    table.kind = ChannelKind::Spectral;
    table.wavelengthsNm = std::move(wavelengths);
    return;
  }
  const auto is = [](const std::string& name, char letter) {
    return name.size() == 1 && std::toupper(static_cast<unsigned char>(name[0])) == letter;
  };
  if (names.size() == 3 && is(names[0], 'R') && is(names[1], 'G') && is(names[2], 'B')) {
    table.kind = ChannelKind::Trichromatic;
    table.notes.push_back("RGB channels are taken as stored; the file does not say which primaries they use");
    return;
  }
  if (names.size() == 1 && wavelengths.empty()) {
    table.kind = ChannelKind::Monochrome;
    return;
  }
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ",") + name;
  throw malformed(
      file, line,
      "channels must be wavelengths ('400nm,410nm,...'), 'R,G,B' or one single channel; got '" + printable(list) + "'");
}

// The VARS line's value: theta_i,phi_i,theta_s,phi_s and the channels' names.
void readVars(std::string_view value, const std::string& file, int line, MeasuredTable& table) {
  const std::vector<std::string_view> names = measured::splitOn(value, ',');
  static constexpr std::string_view kAngles[4] = {"theta_i", "phi_i", "theta_s", "phi_s"};
  for (std::size_t k = 0; k < 4; ++k)
    if (names.size() <= k || names[k] != kAngles[k])
      throw malformed(file, line,
                      "VARS must start with theta_i,phi_i,theta_s,phi_s; got '" + printable(value, 80) + "'");
  if (names.size() < 5) throw malformed(file, line, "VARS names no channel after the four angles");
  for (std::size_t c = 4; c < names.size(); ++c) {
    if (names[c].empty()) throw malformed(file, line, "VARS has an empty name at position " + std::to_string(c + 1));
    table.channelNames.emplace_back(names[c]);
  }
  classifyChannels(table, file, line);
}

// What an ASTM file's header said, as far as it has been read.
struct AstmHeader {
  bool haveVars = false;
  std::optional<long long> numPoints;
  int numPointsLine = 0;
};

// One header line 'KEY value', kept in table.header; NUM_POINTS and VARS are read.
void readAstmHeaderLine(std::string_view text, const std::string& file, int line, MeasuredTable& table,
                        AstmHeader& header) {
  if (startsLikeNumber(text))
    throw malformed(
        file, line,
        "a data row before the VARS line (the header must end with 'VARS theta_i,phi_i,theta_s,phi_s,...')");
  const std::size_t space = text.find_first_of(" \t");
  const std::string_view key = text.substr(0, space);
  const std::string_view value =
      space == std::string_view::npos ? std::string_view() : measured::trim(text.substr(space));
  if (!isHeaderKey(key))
    throw malformed(file, line, "expected a header line 'KEY value', got '" + printable(text, 80) + "'");
  table.header.emplace_back(std::string(key), std::string(value));
  if (key == "NUM_POINTS") {
    header.numPoints = measured::parseCount(value);
    if (!header.numPoints)
      throw malformed(file, line, "NUM_POINTS '" + printable(value, 40) + "' is not a whole number");
    header.numPointsLine = line;
  } else if (key == "VARS") {
    readVars(value, file, line, table);
    header.haveVars = true;
  }
}

// After the last line: a VARS line, as many rows as NUM_POINTS says, at least one.
void checkAstmRows(const AstmHeader& header, std::size_t rows, const std::string& file, int lastLine,
                   MeasuredTable& table) {
  if (!header.haveVars)
    throw malformed(file, lastLine,
                    "no VARS line: the header must end with 'VARS theta_i,phi_i,theta_s,phi_s,<channels>'");
  if (header.numPoints && static_cast<long long>(rows) != *header.numPoints)
    throw malformed(file, lastLine,
                    "the file ends after " + std::to_string(rows) + " rows, but NUM_POINTS (line " +
                        std::to_string(header.numPointsLine) + ") says " + std::to_string(*header.numPoints) +
                        " (truncated?)");
  if (rows == 0) throw malformed(file, lastLine, "no data rows after the VARS line");
  if (!header.numPoints)
    table.notes.push_back("no NUM_POINTS line: the row count (" + std::to_string(rows) + ") was not checked");
}

}  // namespace

MeasuredTable readAstm(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string content = measured::readFileBytes(path);
  const std::vector<measured::TextLine> lines = measured::splitLines(content);

  MeasuredTable table;
  table.sourceFile = file;
  table.format = TableFormat::Astm;
  RowCollector rows;
  AstmHeader header;

  for (const measured::TextLine& line : lines) {
    const std::string_view text = measured::trim(line.text);
    if (text.empty()) continue;

    if (!header.haveVars) {
      readAstmHeaderLine(text, file, line.number, table, header);
      rows.channels = table.channelNames.size();  // the VARS line's channels (none before it)
      continue;
    }

    const std::vector<std::string_view> fields = measured::splitOn(text, ',');
    if (fields.size() != 4 + rows.channels)
      throw malformed(file, line.number,
                      columnCountMessage(4 + rows.channels, fields.size(), "comma-separated",
                                         line.number == lines.back().number && measured::lacksFinalNewline(content)));
    if (header.numPoints && static_cast<long long>(rows.angles.size()) == *header.numPoints)
      throw malformed(file, line.number,
                      "more rows than NUM_POINTS " + std::to_string(*header.numPoints) + " (line " +
                          std::to_string(header.numPointsLine) + ")");
    parseRow(fields, file, line.number, rows);
  }

  checkAstmRows(header, rows.angles.size(), file, lines.empty() ? 0 : lines.back().number, table);
  rows.finish(table);
  measured::noteNegativeValues(table);
  return table;
}

MeasuredTable readPbrt(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string content = measured::readFileBytes(path);
  const std::vector<measured::TextLine> lines = measured::splitLines(content);

  MeasuredTable table;
  table.sourceFile = file;
  table.format = TableFormat::Pbrt;
  table.kind = ChannelKind::Spectral;
  RowCollector rows;
  std::optional<std::size_t> wavelengthCount;

  for (const measured::TextLine& line : lines) {
    std::string_view text = line.text;
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos) {
      table.header.emplace_back("#", std::string(measured::trim(text.substr(hash + 1))));
      text = text.substr(0, hash);
    }
    const std::vector<std::string_view> tokens = measured::splitWhitespace(text);
    if (tokens.empty()) continue;
    std::size_t next = 0;

    if (!wavelengthCount) {
      const std::optional<long long> count = measured::parseCount(tokens[0]);
      if (!count || *count < 1 || *count > 100000)
        throw malformed(
            file, line.number,
            "expected the number of wavelengths (a positive whole number), got '" + printable(tokens[0], 40) + "'");
      wavelengthCount = static_cast<std::size_t>(*count);
      next = 1;
    }
    if (table.wavelengthsNm.size() < *wavelengthCount) {
      for (; next < tokens.size() && table.wavelengthsNm.size() < *wavelengthCount; ++next) {
        const double w = measured::finiteField(tokens[next], file, line.number, "wavelength");
        if (!(w > 0.0) || (!table.wavelengthsNm.empty() && !(w > table.wavelengthsNm.back())))
          throw malformed(file, line.number,
                          "wavelengths must be positive and increasing, got " + measured::formatShortest(w) + " nm");
        table.wavelengthsNm.push_back(w);
      }
      if (next < tokens.size())
        throw malformed(file, line.number,
                        "values after the " + std::to_string(*wavelengthCount) +
                            " wavelengths on the same line (samples start on a new line)");
      if (table.wavelengthsNm.size() == *wavelengthCount) {
        for (double w : table.wavelengthsNm) table.channelNames.push_back(measured::wavelengthChannelName(w));
        rows.channels = *wavelengthCount;
      }
      continue;
    }

    if (tokens.size() != 4 + rows.channels)
      throw malformed(file, line.number,
                      columnCountMessage(4 + rows.channels, tokens.size(), "whitespace-separated",
                                         line.number == lines.back().number && measured::lacksFinalNewline(content)));
    parseRow(tokens, file, line.number, rows);
  }

  const int lastLine = lines.empty() ? 0 : lines.back().number;
  if (!wavelengthCount) throw malformed(file, lastLine, "no data: expected the number of wavelengths");
  if (table.wavelengthsNm.size() < *wavelengthCount)
    throw malformed(file, lastLine,
                    "the file ends after " + std::to_string(table.wavelengthsNm.size()) + " of " +
                        std::to_string(*wavelengthCount) + " wavelengths (truncated?)");
  if (rows.angles.empty()) throw malformed(file, lastLine, "no samples after the wavelengths");
  rows.finish(table);
  measured::noteNegativeValues(table);
  return table;
}

void writeAstm(const std::filesystem::path& path, const MeasuredTable& table) {
  table.validate();
  std::string text;
  for (const auto& [key, value] : table.header)
    if (key != "NUM_POINTS" && key != "VARS" && isHeaderKey(key))
      text += key + (value.empty() ? "" : " " + value) + "\n";
  text += "NUM_POINTS " + std::to_string(table.size()) + "\n";
  text += "VARS theta_i,phi_i,theta_s,phi_s";
  for (std::size_t c = 0; c < table.channelCount(); ++c) {
    std::string name;
    switch (table.kind) {
      case ChannelKind::Spectral:
        name = measured::wavelengthChannelName(table.wavelengthsNm[c]);
        break;
      case ChannelKind::Trichromatic:
        name = std::string(1, "RGB"[c]);
        break;
      case ChannelKind::Monochrome: {
        // A name that would read back as a wavelength, or break the row, is replaced.
        const std::string& own = table.channelNames[c];
        const bool usable = isHeaderKey(own) && !measured::wavelengthFromChannelName(own);
        name = usable ? own : "BRDF";
        break;
      }
    }
    text += "," + name;
  }
  text += "\n\n";
  for (std::size_t i = 0; i < table.size(); ++i) {
    const SampleAngles& a = table.angles[i];
    text += measured::formatShortest(a.thetaIn) + "," + measured::formatShortest(a.phiIn) + "," +
            measured::formatShortest(a.thetaOut) + "," + measured::formatShortest(a.phiOut);
    for (Eigen::Index c = 0; c < table.values.cols(); ++c)
      text += "," + measured::formatShortest(table.values(static_cast<Eigen::Index>(i), c));
    text += "\n";
  }
  writeFileAtomically(path, text);
}

}  // namespace brdfbake
