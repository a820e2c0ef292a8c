// Bounded JSON parsing: hostile nesting and out-of-range numbers are errors naming the source and
// the JSON path, never crashes or stray exceptions.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/json_text.hpp>

#include <string>

namespace brdfbake {
namespace {

std::string nestedArrays(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']');
}

std::string errorFor(const std::string& text) {
  try {
    parseJsonText(text, "in.json");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    return e.what();
  }
  return "(no error)";
}

TEST(JsonText, NestingUpToTheLimitParses) {
  const nlohmann::json parsed = parseJsonText(nestedArrays(kMaxJsonDepth), "in.json");
  int depth = 0;
  for (const nlohmann::json* v = &parsed; v->is_array(); v = v->empty() ? nullptr : &(*v)[0]) {
    ++depth;
    if (v->empty()) break;
  }
  EXPECT_EQ(depth, kMaxJsonDepth);
}

TEST(JsonText, NestingBeyondTheLimitIsAnErrorWithFileAndPath) {
  const std::string message = errorFor(nestedArrays(kMaxJsonDepth + 1));
  EXPECT_EQ(message.rfind("in.json: [0][0]", 0), 0u) << message;
  EXPECT_NE(message.find("nested more than 64 levels"), std::string::npos) << message;
}

TEST(JsonText, HundredThousandLevelsFailFastWithAShortMessage) {
  const std::string message = errorFor("{\"maps\":" + nestedArrays(100000) + "}");
  EXPECT_EQ(message.rfind("in.json: maps[0][0]", 0), 0u) << message.substr(0, 80);
  EXPECT_LT(message.size(), 400u);
}

TEST(JsonText, NumberBeyondTheDoubleRangeNamesItsPath) {
  EXPECT_EQ(errorFor(R"({"maps": [{"lights": [{"color": [1, 1e400, 0]}]}]})"),
            "in.json: maps[0].lights[0].color[1]: number out of range (beyond the largest double, about 1.8e308)");
  EXPECT_EQ(errorFor(R"({"a": 1e400})"), "in.json: a: number out of range (beyond the largest double, about 1.8e308)");
  EXPECT_EQ(errorFor("-1e400"), "in.json: (root): number out of range (beyond the largest double, about 1.8e308)");
}

TEST(JsonText, SyntaxErrorsGiveLineAndColumn) {
  const std::string message = errorFor("{\n  \"a\": 1,\n  \"b\" 2\n}");
  EXPECT_EQ(message.rfind("in.json:3:", 0), 0u) << message;
  EXPECT_NE(message.find("invalid JSON"), std::string::npos);
}

TEST(JsonText, LargestFiniteNumbersParse) {
  const nlohmann::json v = parseJsonText("[1.7976931348623157e308, -1e308, 5e-324]", "in.json");
  EXPECT_DOUBLE_EQ(v[0].get<double>(), 1.7976931348623157e308);
  EXPECT_DOUBLE_EQ(v[1].get<double>(), -1e308);
}

}  // namespace
}  // namespace brdfbake
