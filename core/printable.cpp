#include <brdfbake/core/printable.hpp>

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace brdfbake {
namespace {

// The length of the valid UTF-8 sequence at text[at] (RFC 3629: no overlong forms, no surrogates,
// nothing beyond U+10FFFF), or 0 if the bytes there are not one; `codePoint` receives its value.
std::size_t utf8Sequence(std::string_view text, std::size_t at, std::uint32_t& codePoint) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[at + i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  std::uint32_t minimum = 0;
  if (lead < 0x80) {
    codePoint = lead;
    return 1;
  } else if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2, minimum = 0x80, codePoint = lead & 0x1Fu;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3, minimum = 0x800, codePoint = lead & 0x0Fu;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4, minimum = 0x10000, codePoint = lead & 0x07u;
  } else {
    return 0;
  }
  if (text.size() - at < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0u) != 0x80u) return 0;
    codePoint = (codePoint << 6) | (byte(i) & 0x3Fu);
  }
  if (codePoint < minimum || codePoint > 0x10FFFF || (codePoint >= 0xD800 && codePoint <= 0xDFFF)) return 0;
  return length;
}

bool invisibleOrControl(std::uint32_t c) {
  return (c >= 0x80 && c <= 0x9F) || c == 0x200E || c == 0x200F || c == 0x2028 || c == 0x2029 ||
         (c >= 0x202A && c <= 0x202E) || (c >= 0x2066 && c <= 0x2069);
}

void appendHex(std::string& out, std::uint32_t value, int digits) {
  static const char kDigits[] = "0123456789abcdef";
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) out += kDigits[(value >> shift) & 0xFu];
}

// Escapes text[begin, end) into `out`; newlines and tabs are kept when `keepLayout`.
void appendEscaped(std::string& out, std::string_view text, bool keepLayout) {
  std::size_t at = 0;
  while (at < text.size()) {
    std::uint32_t c = 0;
    const std::size_t length = utf8Sequence(text, at, c);
    if (length == 0 || (length == 1 && (c < 0x20 || c == 0x7F) && !(keepLayout && (c == '\n' || c == '\t')))) {
      out += "\\x";
      appendHex(out, static_cast<unsigned char>(text[at]), 2);
      ++at;
    } else if (invisibleOrControl(c)) {
      out += "\\u{";
      appendHex(out, c, 4);
      out += '}';
      at += length;
    } else {
      out.append(text.substr(at, length));
      at += length;
    }
  }
}

// Moves `cut` back (or forward, `forward`) to the start of a UTF-8 sequence, at most 3 bytes.
std::size_t characterBoundary(std::string_view text, std::size_t cut, bool forward) {
  for (int i = 0; i < 3 && cut > 0 && cut < text.size(); ++i) {
    if ((static_cast<unsigned char>(text[cut]) & 0xC0u) != 0x80u) break;
    forward ? ++cut : --cut;
  }
  return cut;
}

std::string shortened(std::string_view text, std::size_t limit, bool keepLayout) {
  std::string out;
  if (text.size() <= limit) {
    appendEscaped(out, text, keepLayout);
    return out;
  }
  const std::size_t half = limit / 2;
  const std::size_t headEnd = characterBoundary(text, half, false);
  const std::size_t tailBegin = characterBoundary(text, text.size() - half, true);
  appendEscaped(out, text.substr(0, headEnd), keepLayout);
  out += "...";
  appendEscaped(out, text.substr(tailBegin), keepLayout);
  out += " (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace

std::string printable(std::string_view text, std::size_t limit) { return shortened(text, limit, false); }

std::string printableMessage(std::string_view message, std::size_t lineLimit) {
  std::string out;
  std::size_t begin = 0;
  while (begin <= message.size()) {
    const std::size_t end = std::min(message.find('\n', begin), message.size());
    out += shortened(message.substr(begin, end - begin), lineLimit, true);
    if (end == message.size()) break;
    out += '\n';
    begin = end + 1;
  }
  return out;
}

std::string formatG(double value, int significant) {
  std::ostringstream out;
  out.precision(significant);
  out << value;
  return out.str();
}

}  // namespace brdfbake
