#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/sample_output.hpp>

#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

// "x y z" per line; '#' starts a comment; blank lines are skipped. Errors name FILE:LINE.
std::vector<SampleResult::Lookup> readDirectionsFile(const fs::path& file) {
  std::istringstream in(readTextFile(file, "directions file"));
  std::vector<SampleResult::Lookup> directions;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const std::string content = text.substr(0, text.find('#'));
    std::istringstream fields(content);
    std::vector<std::string> words;
    for (std::string word; fields >> word;) words.push_back(word);
    if (words.empty()) continue;
    if (words.size() != 3) {
      throw Error::atFile(Error::Kind::InvalidInput, file.string(), line,
                          "expected three numbers \"x y z\", got '" + shortenForMessage(content, 80) + "'");
    }
    Vec3 d;
    for (int i = 0; i < 3; ++i) {
      const std::string& word = words[static_cast<std::size_t>(i)];
      const std::optional<double> value = finiteNumberIn(word);
      if (!value) {
        throw Error::atFile(Error::Kind::InvalidInput, file.string(), line,
                            "'" + shortenForMessage(word, 40) + "' is not a finite number");
      }
      d[i] = *value;
    }
    if (!(d.norm() > 0.0)) {
      throw Error::atFile(Error::Kind::InvalidInput, file.string(), line, "the direction must be non-zero");
    }
    directions.push_back({d, line, Rgba::Zero()});
  }
  if (directions.empty()) {
    throw Error(Error::Kind::InvalidInput,
                shortenForMessage(file.string()) + ": no directions (one \"x y z\" per line)");
  }
  return directions;
}

nlohmann::json lookupJson(const SampleResult& result, const SampleResult::Lookup& lookup) {
  const Rgba& v = lookup.value;
  nlohmann::json entry = {{"value", {v[0], v[1], v[2], v[3]}}};
  if (result.usesDirection) entry["direction"] = {lookup.direction.x(), lookup.direction.y(), lookup.direction.z()};
  if (result.cosView) entry["cos_view"] = *result.cosView;
  if (lookup.line > 0) entry["line"] = lookup.line;
  return entry;
}

}  // namespace

BakedOutput OutputSource::open(const std::string& fromName) const {
  OpenOutputOptions options;
  options.from = from;
  options.fromName = fromName;
  options.mipLevel = mipLevel;
  return BakedOutput::open(path, options);
}

void OutputSource::checkCosView(const BakedOutput& output, bool fresnelNeedsIt) const {
  const bool stack = output.kind() == OutputKind::ElevationStack, table = output.kind() == OutputKind::FresnelTable;
  const bool needs = stack || (fresnelNeedsIt && table);
  if (needs && !cosView) {
    throw Error::invalidField(
        "cos_view", std::string("a") +
                        (stack ? "n elevation stack is interpolated at n.v" : " Fresnel table is read at n.v") +
                        "; give n.v in [0, 1]");
  }
  if (cosView && !stack && !table) {
    throw Error::invalidField("cos_view", "a " + std::string(toString(output.kind())) +
                                              " is looked up by direction alone (n.v applies to elevation stacks "
                                              "and Fresnel tables)");
  }
  if (cosView && !needs) {
    throw Error::invalidField("cos_view", "here a Fresnel table takes n.v from each direction (the view +z)");
  }
}

void SampleOptions::validate() const {
  requireField(directions.empty() || directionsFile.empty(), "directions",
               "give directions or a directions file, not both");
  for (const auto& d : directions) requireField(d.allFinite() && d.norm() > 0.0, "directions", "must be non-zero");
}

SampleResult sampleOutput(const SampleOptions& options, const Context& context) {
  context.checkCancelled();
  options.validate();
  const BakedOutput output = options.source.open();
  options.source.checkCosView(output);
  SampleResult result;
  result.usesDirection = output.usesDirection();
  result.cosView = options.source.cosView;
  result.fromFile = !options.directionsFile.empty();
  if (result.fromFile) result.lookups = readDirectionsFile(options.directionsFile);
  for (const auto& d : options.directions) result.lookups.push_back({d, 0, Rgba::Zero()});
  if (!result.usesDirection && !result.lookups.empty()) {
    throw Error(Error::Kind::InvalidArgument, "a Fresnel table is a function of n.v alone: give cos_view only");
  }
  if (result.usesDirection && result.lookups.empty()) {
    throw Error(Error::Kind::InvalidArgument, "a " + std::string(toString(output.kind())) +
                                                  " is looked up at a direction: give one (or a file of them)");
  }
  if (result.lookups.empty()) result.lookups.push_back({Vec3::UnitZ(), 0, Rgba::Zero()});  // n.v alone
  for (auto& lookup : result.lookups) lookup.value = output.lookup(lookup.direction, options.source.cosView);
  return result;
}

std::string SampleResult::briefReport() const {
  std::ostringstream text;
  for (const auto& lookup : lookups) {
    const Rgba& v = lookup.value;
    text << v[0] << " " << v[1] << " " << v[2] << " " << v[3] << "\n";
  }
  return text.str();
}

nlohmann::json SampleResult::toJson() const {
  if (!fromFile) return lookupJson(*this, lookups.front());
  nlohmann::json array = nlohmann::json::array();
  for (const auto& lookup : lookups) array.push_back(lookupJson(*this, lookup));
  return array;
}

}  // namespace brdfbake
