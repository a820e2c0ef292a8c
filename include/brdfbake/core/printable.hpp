#pragma once
/// @file
/// The one way untrusted text (file names, JSON keys and strings, header lines of tables, values of
/// environment variables, another program's messages) enters a message: printable() makes it safe to
/// show on a terminal and bounds its length, so a hostile name can neither drive the terminal
/// (escape sequences, a forged "brdfbake: ..." line after a newline) nor flood it (a 1 MB key).

#include <cstddef>
#include <string>
#include <string_view>

namespace brdfbake {

/// The longest piece of untrusted text printable() shows whole by default, in bytes.
inline constexpr std::size_t kPrintableLimit = 200;

/// `text` made safe for a message:
///   - C0 controls (newline and tab included), DEL, and bytes that are not valid UTF-8 (stray
///     continuation bytes, overlong forms, surrogates, truncated sequences) become `\xHH`
///     ("\x1b" for ESC, "\x00" for NUL);
///   - C1 controls (U+0080..U+009F) and the invisible characters that reorder or break lines
///     (U+200E, U+200F, U+2028, U+2029, U+202A..U+202E, U+2066..U+2069) become `\u{HHHH}`;
///   - valid UTF-8 otherwise is kept as it is;
///   - text longer than `limit` bytes keeps its first and last limit/2 bytes (cut at character
///     boundaries) around "...", followed by the full length: "aaaa...zzzz (52428800 bytes)".
std::string printable(std::string_view text, std::size_t limit = kPrintableLimit);

/// A whole message made safe for a terminal (the CLI's last step before printing): as printable(),
/// except that the message's own newlines are kept (so are tabs), and each line is shortened
/// separately to `lineLimit` bytes.
std::string printableMessage(std::string_view message, std::size_t lineLimit = 4096);

/// `value` as a report prints it: `significant` significant digits, in the shorter of fixed and
/// scientific notation (printf's %g): formatG(0.12634) == "0.126", formatG(1234.5) == "1.23e+03".
std::string formatG(double value, int significant = 3);

}  // namespace brdfbake
