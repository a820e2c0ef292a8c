// Bounded JSON parsing: hostile nesting and out-of-range numbers are errors naming the source and
// the JSON path, never crashes or stray exceptions.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/json_reader.hpp>
#include <brdfbake/io/json_text.hpp>

#include <fstream>
#include <string>

#include "test_support.hpp"

namespace brdfbake {
namespace {

std::string nestedArrays(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']');
}

// The message of the InvalidInput error parsing `text` throws.
std::string errorFor(const std::string& text) {
  return test::errorOf([&] { parseJsonText(text, "in.json"); }, Error::Kind::InvalidInput);
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

TEST(JsonText, NulInAStringOrKeyIsRefusedWithItsPath) {
  EXPECT_EQ(errorFor(R"({"maps": [{"output": "x\u0000.exr"}]})"),
            "in.json: maps[0].output: contains a NUL character (\\u0000), which no name or value may hold");
  EXPECT_EQ(errorFor(R"({"maps": [{"a\u0000b": 1}]})"),
            "in.json: maps[0] (a key): contains a NUL character (\\u0000), which no name or value may hold");
}

TEST(JsonText, KeysInPathsAreShownPrintable) {
  const std::string message = errorFor("{\"\\u001b]0;pwned\\u0007\": [1e400]}");
  EXPECT_EQ(message, "in.json: \\x1b]0;pwned\\x07[0]: number out of range (beyond the largest double, about 1.8e308)");
}

TEST(JsonText, ArraysOfObjectsParseWhole) {
  // 200,000 objects: the callback parser took 7 s here (quadratic); the builder is linear.
  std::string text = "[";
  for (int i = 0; i < 200000; ++i) text += i ? ",{\"a\":" + std::to_string(i) + "}" : "{\"a\":0}";
  text += "]";
  const nlohmann::json parsed = parseJsonText(text, "in.json");
  ASSERT_EQ(parsed.size(), 200000u);
  EXPECT_EQ(parsed[199999]["a"].get<int>(), 199999);
  EXPECT_EQ(parsed, nlohmann::json::parse(text));  // the same document as nlohmann's own parser
}

TEST(JsonText, DuplicateKeysKeepTheLastValueAsNlohmannDoes) {
  const std::string text = R"({"a": 1, "b": {"c": [1, {"d": null}]}, "a": 2})";
  EXPECT_EQ(parseJsonText(text, "in.json"), nlohmann::json::parse(text));
}

TEST(JsonText, InputsOverTheSizeLimitAreRefusedBeforeParsing) {
  const std::string big(kMaxJsonBytes + 1, ' ');
  EXPECT_EQ(errorFor(big), "in.json: 16777217 bytes of JSON, more than the 16 MiB accepted (docs/limits.md)");
  test::TempDir dir;
  std::ofstream(dir / "big.json") << "[" << std::string(kMaxJsonBytes, ' ') << "]";
  try {
    readJsonFile(dir / "big.json");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("big.json: 16777218 bytes of JSON"), std::string::npos) << e.what();
  }
}

TEST(JsonObjectReader, UnknownKeysAndValuesArePrintableAndShort) {
  const nlohmann::json doc = nlohmann::json::parse("{\"\\u001b[2J\": 1, \"k\": \"" + std::string(100000, 'v') + "\"}");
  JsonObjectReader reader(doc, "maps[0]");
  try {
    reader.integer("k", 0, 10);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u) << e.what();
  }
  reader.find("k");
  try {
    reader.finish();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "maps[0].\\x1b[2J: unknown key (known keys: k)");
  }
}

TEST(JsonObjectReader, HugeUnsignedIntegersAreShownAsGiven) {
  const nlohmann::json doc = nlohmann::json::parse(R"({"resolution": 18446744073709551615, "n": 3000000000})");
  JsonObjectReader reader(doc, "maps[0]");
  EXPECT_THROW(
      {
        try {
          reader.integer("resolution", 1, 65536);
        } catch (const Error& e) {
          EXPECT_STREQ(e.what(), "maps[0].resolution: must be in [1, 65536], got 18446744073709551615");
          throw;
        }
      },
      Error);
  EXPECT_THROW(reader.integer("n", 0, 2147483647), Error);
}

TEST(JsonObjectReader, ArraysAndColoursHaveLimits) {
  const nlohmann::json doc = {{"lights", nlohmann::json::array()}, {"color", {1, 1e308, 0}}, {"grey", 1e6}};
  nlohmann::json many = doc;
  for (int i = 0; i < 300; ++i) many["lights"].push_back(i);
  JsonObjectReader reader(many, "maps[0]");
  EXPECT_EQ(reader.array("lights", 300).size(), 300u);
  try {
    reader.array("lights", 256);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "maps[0].lights: at most 256 entries (docs/limits.md), got 300");
  }
  try {
    reader.color("color");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_EQ(std::string(e.what()).rfind("maps[0].color: must be <= 1e+06 per channel", 0), 0u) << e.what();
  }
  EXPECT_EQ(reader.color("grey")[1], 1e6);
}

}  // namespace
}  // namespace brdfbake
