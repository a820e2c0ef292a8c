// printable(): the one way untrusted text reaches a message. The expected strings are written out by
// hand from the rules in core/printable.hpp (the escapes, the UTF-8 validity rules of RFC 3629).
#include <gtest/gtest.h>
#include <brdfbake/core/printable.hpp>

#include <string>

namespace brdfbake {
namespace {

// True when `text` holds only printable ASCII and valid multi-byte UTF-8 (no controls at all).
bool onlyPrintable(const std::string& text) {
  for (unsigned char c : text)
    if (c < 0x20 || c == 0x7F) return false;
  return true;
}

TEST(Printable, TerminalControlsAreEscaped) {
  EXPECT_EQ(printable("\x1b]0;pwned\x07\x1b[2J"), "\\x1b]0;pwned\\x07\\x1b[2J");
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable("x\ny\r\tz\x7f"), "x\\x0ay\\x0d\\x09z\\x7f");
  // A newline can no longer forge a line of its own.
  EXPECT_EQ(printable("a.exr\nbrdfbake: error: forged").find('\n'), std::string::npos);
}

TEST(Printable, C1ControlsAndInvisibleReorderingCharactersAreEscaped) {
  EXPECT_EQ(printable("\xc2\x9b"
                      "2J"),
            "\\u{009b}2J");  // U+009B, the 8-bit CSI
  EXPECT_EQ(printable("ab\xe2\x80\xae"
                      "cd"),
            "ab\\u{202e}cd");                         // RIGHT-TO-LEFT OVERRIDE
  EXPECT_EQ(printable("\xe2\x80\xa8"), "\\u{2028}");  // LINE SEPARATOR
}

TEST(Printable, InvalidUtf8BytesAreEscapedOneByOne) {
  EXPECT_EQ(printable("\xff"), "\\xff");
  EXPECT_EQ(printable("a\x80z"), "a\\x80z");                         // a stray continuation byte
  EXPECT_EQ(printable("\xc0\x80"), "\\xc0\\x80");                    // overlong NUL
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a UTF-16 surrogate
  EXPECT_EQ(printable("\xe2\x82"), "\\xe2\\x82");                    // cut short
  EXPECT_EQ(printable("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
  EXPECT_EQ(printable("\x9b"), "\\x9b");                             // a raw 8-bit CSI byte
}

TEST(Printable, ValidUtf8IsKept) {
  const std::string text = "caf\xc3\xa9 \xe6\x97\xa5\xe6\x9c\xac \xf0\x9f\x8c\x88 ~!";  // café 日本 🌈
  EXPECT_EQ(printable(text), text);
}

TEST(Printable, LongTextKeepsItsEndsAndGivesItsLength) {
  EXPECT_EQ(printable("short"), "short");
  const std::string huge = std::string(25'000'000, 'a') + std::string(25'000'000, 'z');
  const std::string shown = printable(huge);
  EXPECT_EQ(shown, std::string(100, 'a') + "..." + std::string(100, 'z') + " (50000000 bytes)");
  EXPECT_EQ(printable(std::string(300, 'x'), 20), std::string(10, 'x') + "..." + std::string(10, 'x') + " (300 bytes)");
}

TEST(Printable, ShorteningNeverCutsACharacterInTwo) {
  std::string text;
  for (int i = 0; i < 200; ++i) text += "\xe6\x97\xa5";  // 600 bytes of 3-byte characters
  const std::string shown = printable(text, 100);
  // 50 bytes from each end, moved back (head) or on (tail) to whole characters: 48 bytes each.
  std::string expected;
  for (int i = 0; i < 16; ++i) expected += "\xe6\x97\xa5";
  EXPECT_EQ(shown, expected + "..." + expected + " (600 bytes)");
  EXPECT_EQ(shown.find("\\x"), std::string::npos) << shown;
}

TEST(PrintableMessage, KeepsTheMessagesOwnLinesOnly) {
  EXPECT_EQ(printableMessage("line one\n\tline two\x1b[31m\n"), "line one\n\tline two\\x1b[31m\n");
  const std::string long_line(10'000, 'q');
  const std::string shown = printableMessage("a\n" + long_line + "\nb", 100);
  EXPECT_EQ(shown, "a\n" + std::string(50, 'q') + "..." + std::string(50, 'q') + " (10000 bytes)\nb");
  std::string every;
  for (int c = 0; c < 256; ++c)
    if (c != '\n' && c != '\t') every += static_cast<char>(c);
  EXPECT_TRUE(onlyPrintable(printableMessage(every)));
  EXPECT_TRUE(onlyPrintable(printable(every + "\n\t")));
}

}  // namespace
}  // namespace brdfbake
