#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/json_text.hpp>

#include <algorithm>
#include <vector>

namespace brdfbake {
namespace {

// Tracks where the parser is ("maps[2].material.exponent") from the parser's callback events, so
// errors raised inside the parser can name a JSON path.
class JsonPathTracker {
 public:
  bool onEvent(int depth, nlohmann::json::parse_event_t event, const nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        countValueInParent();
        frames_.push_back({event == Event::array_start, -1, {}});
        if (depth >= kMaxJsonDepth) throw TooDeep{};
        break;
      case Event::key:
        frames_.back().key = parsed.get<std::string>();
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        break;
      case Event::value:
        countValueInParent();
        break;
    }
    return true;
  }

  // The path of the value being parsed now (the next element for an array).
  std::string path() const {
    std::string out;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (f.array) {
        const long index = (i + 1 == frames_.size()) ? f.index + 1 : f.index;
        out += '[';
        out += std::to_string(std::max(index, 0L));
        out += ']';
      } else if (!f.key.empty() || i + 1 < frames_.size()) {
        if (!out.empty()) out += '.';
        out += f.key;
      }
    }
    return out.empty() ? "(root)" : shortenForMessage(out, 120);
  }

  struct TooDeep {};

 private:
  struct Frame {
    bool array;
    long index;
    std::string key;
  };
  void countValueInParent() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }
  std::vector<Frame> frames_;
};

std::string lineAndColumn(std::string_view text, std::size_t byte) {
  const std::size_t offset = std::min<std::size_t>(byte > 0 ? byte - 1 : 0, text.size());
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n')
      ++line, column = 1;
    else
      ++column;
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

}  // namespace

nlohmann::json parseJsonText(std::string_view text, const std::string& source) {
  JsonPathTracker tracker;
  const std::string label = shortenForMessage(source);
  try {
    return nlohmann::json::parse(text.begin(), text.end(),
                                 [&tracker](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
                                   return tracker.onEvent(depth, event, parsed);
                                 });
  } catch (const JsonPathTracker::TooDeep&) {
    throw Error(Error::Kind::InvalidInput, label + ": " + tracker.path() + ": nested more than " +
                                               std::to_string(kMaxJsonDepth) +
                                               " levels deep (the limit for JSON input)");
  } catch (const nlohmann::json::parse_error& e) {
    std::string message = e.what();
    if (const auto pos = message.find("syntax error"); pos != std::string::npos) message = message.substr(pos);
    throw Error(Error::Kind::InvalidInput,
                label + ":" + lineAndColumn(text, e.byte) + ": invalid JSON: " + shortenForMessage(message));
  } catch (const nlohmann::json::out_of_range&) {
    throw Error(Error::Kind::InvalidInput,
                label + ": " + tracker.path() + ": number out of range (beyond the largest double, about 1.8e308)");
  } catch (const nlohmann::json::exception& e) {
    throw Error(Error::Kind::InvalidInput,
                label + ": " + tracker.path() + ": invalid JSON: " + shortenForMessage(e.what()));
  }
}

nlohmann::json readJsonFile(const std::filesystem::path& path) {
  return parseJsonText(readTextFile(path, "JSON file"), path.string());
}

}  // namespace brdfbake
