#include <brdfbake/core/error.hpp>
#include <brdfbake/core/text_numbers.hpp>

#include <gtest/gtest.h>

namespace brdfbake {
namespace {

TEST(TextNumbers, ReadsAWholeFiniteNumberAndNothingElse) {
  EXPECT_EQ(finiteNumberIn("0.25"), 0.25);
  EXPECT_EQ(finiteNumberIn(" -1e3\t"), -1000.0);
  EXPECT_EQ(finiteNumberIn("+2"), 2.0);
  EXPECT_EQ(finiteNumberIn(".5"), 0.5);
  for (const char* bad : {"", " ", "1x", "x1", "1 2", "nan", "inf", "-inf", "1e999", "+-1", "++1", "0x10", "1,5"}) {
    EXPECT_FALSE(finiteNumberIn(bad).has_value()) << bad;
  }
}

TEST(TextNumbers, ReadsWholeNumbersWithinIntsRange) {
  EXPECT_EQ(wholeNumberIn("42"), 42);
  EXPECT_EQ(wholeNumberIn(" -7 "), -7);
  EXPECT_EQ(wholeNumberIn("+3"), 3);
  EXPECT_EQ(wholeNumberIn("2147483647"), 2147483647);
  for (const char* bad : {"", "1.0", "1e3", "2147483648", "-2147483649", "4x", "0.5"}) {
    EXPECT_FALSE(wholeNumberIn(bad).has_value()) << bad;
  }
}

TEST(TextNumbers, ParseSaysWhatItExpectedAndQuotesTheTextSafely) {
  EXPECT_EQ(parseFiniteNumber("1.5"), 1.5);
  EXPECT_EQ(parseWholeNumber("12"), 12);
  try {
    parseFiniteNumber("1\x1b[2J");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument);
    EXPECT_EQ(std::string(e.what()), "expected a finite number, got '1\\x1b[2J'");
  }
  try {
    parseWholeNumber("3.5");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "expected a whole number, got '3.5'");
  }
}

}  // namespace
}  // namespace brdfbake
