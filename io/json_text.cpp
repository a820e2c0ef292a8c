#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_text.hpp>

#include <algorithm>
#include <vector>

namespace brdfbake {
namespace {

using json = nlohmann::json;

// Builds the document from the parser's SAX events (nlohmann::json::sax_parse), tracking where it
// is ("maps[2].material.exponent") so every error names a JSON path. Linear in the input: the
// callback parser nlohmann::json::parse(..., callback) uses instead scans the whole parent array
// for discarded values at every end of an object, which made an array of n objects cost O(n^2)
// (2e5 "{}" took 7 s).
class DocumentBuilder {
 public:
  DocumentBuilder(std::string_view text, std::string label) : text_(text), label_(std::move(label)) {}

  json& document() { return root_; }

  bool null() { return place(json(nullptr)); }
  bool boolean(bool value) { return place(json(value)); }
  bool number_integer(json::number_integer_t value) { return place(json(value)); }
  bool number_unsigned(json::number_unsigned_t value) { return place(json(value)); }
  bool number_float(json::number_float_t value, const json::string_t&) { return place(json(value)); }
  bool string(json::string_t& value) {
    refuseNul(value, path());
    return place(json(std::move(value)));
  }
  bool binary(json::binary_t&) { return fail(path() + ": binary values are not JSON"); }
  bool key(json::string_t& value) {
    refuseNul(value, path() + " (a key)");
    frames_.back().key = std::move(value);
    return true;
  }
  bool start_object(std::size_t) { return open(json::object(), false); }
  bool start_array(std::size_t) { return open(json::array(), true); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    if (e.id == 406) {  // out_of_range: a number beyond the double range
      return fail(path() + ": number out of range (beyond the largest double, about 1.8e308)");
    }
    std::string message = e.what();
    if (const auto at = message.find("syntax error"); at != std::string::npos) message = message.substr(at);
    throw Error(Error::Kind::InvalidInput,
                label_ + ":" + lineAndColumn(position) + ": invalid JSON: " + printable(message));
  }

 private:
  struct Frame {
    json* container;
    bool array;
    long index = -1;  // of the last element placed (arrays)
    std::string key;  // of the value being read (objects)
  };

  [[noreturn]] bool fail(const std::string& message) const {
    throw Error(Error::Kind::InvalidInput, label_ + ": " + message);
  }

  void refuseNul(const std::string& value, const std::string& where) const {
    if (value.find('\0') != std::string::npos) {
      fail(where + ": contains a NUL character (\\u0000), which no name or value may hold");
    }
  }

  // Puts `value` where the parser is: the root, the next array element or the current key.
  json* insert(json&& value) {
    if (frames_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& parent = frames_.back();
    if (parent.array) {
      ++parent.index;
      auto& elements = parent.container->get_ref<json::array_t&>();
      elements.push_back(std::move(value));
      return &elements.back();
    }
    json& slot = (*parent.container->get_ptr<json::object_t*>())[parent.key];
    slot = std::move(value);
    return &slot;
  }

  bool place(json&& value) {
    insert(std::move(value));
    return true;
  }

  bool open(json&& container, bool array) {
    if (frames_.size() >= static_cast<std::size_t>(kMaxJsonDepth)) {
      fail(path() + ": nested more than " + std::to_string(kMaxJsonDepth) + " levels deep (the limit for JSON input)");
    }
    // A container's address stays valid while it is open: its parent gets no other element meanwhile.
    json* placed = insert(std::move(container));
    frames_.push_back({placed, array, -1, {}});
    return true;
  }

  bool close() {
    frames_.pop_back();
    return true;
  }

  // The path of the value being parsed now (the next element for an array).
  std::string path() const {
    std::string out;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (f.array) {
        const long index = (i + 1 == frames_.size()) ? f.index + 1 : f.index;
        out += '[' + std::to_string(std::max(index, 0L)) + ']';
      } else if (!f.key.empty() || i + 1 < frames_.size()) {
        if (!out.empty()) out += '.';
        out += printable(f.key, 60);
      }
    }
    return out.empty() ? "(root)" : printable(out, 160);
  }

  std::string lineAndColumn(std::size_t byte) const {
    const std::size_t offset = std::min<std::size_t>(byte > 0 ? byte - 1 : 0, text_.size());
    int line = 1, column = 1;
    for (std::size_t i = 0; i < offset; ++i) {
      if (text_[i] == '\n')
        ++line, column = 1;
      else
        ++column;
    }
    return std::to_string(line) + ":" + std::to_string(column);
  }

  std::string_view text_;
  std::string label_;
  json root_;
  std::vector<Frame> frames_;
};

}  // namespace

namespace {
void requireJsonSize(std::uintmax_t bytes, const std::string& label) {
  if (bytes > kMaxJsonBytes) {
    throw Error(Error::Kind::InvalidInput, label + ": " + std::to_string(bytes) + " bytes of JSON, more than the " +
                                               std::to_string(kMaxJsonBytes >> 20) + " MiB accepted (docs/limits.md)");
  }
}
}  // namespace

nlohmann::json parseJsonText(std::string_view text, const std::string& source) {
  const std::string label = printable(source);
  requireJsonSize(text.size(), label);
  DocumentBuilder builder(text, label);
  try {
    if (!json::sax_parse(text.begin(), text.end(), &builder)) {
      throw Error(Error::Kind::InvalidInput, label + ": invalid JSON");
    }
  } catch (const json::exception& e) {  // not expected from sax_parse; named all the same
    throw Error(Error::Kind::InvalidInput, label + ": invalid JSON: " + printable(e.what()));
  }
  return std::move(builder.document());
}

nlohmann::json readJsonFile(const std::filesystem::path& path) {
  requireJsonSize(requireInputFile(path, "JSON file"), printable(path.string()));
  return parseJsonText(readTextFile(path, "JSON file", kMaxJsonBytes), path.string());
}

}  // namespace brdfbake
