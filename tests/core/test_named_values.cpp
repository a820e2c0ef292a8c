// closestName and parseByName: the "did you mean" every front (JSON keys, enum names, the CLI's
// commands and flags) shares. Expected names are worked out by hand from the edit distances.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/maps/parameterization.hpp>

namespace brdfbake {
namespace {

const std::vector<std::string> kKeys = {"max_error", "resolution", "samples_per_texel", "output", "outputs"};

TEST(ClosestName, ATypoWithinTwoEditsIsNamed) {
  EXPECT_EQ(closestName("max_eror", kKeys), "max_error");     // one deletion
  EXPECT_EQ(closestName("resolutoin", kKeys), "resolution");  // a swap: two substitutions
  EXPECT_EQ(closestName("outptu", kKeys), "output");          // two substitutions; "outputs" is three away
}

TEST(ClosestName, AWordNearNothingIsNotNamed) {
  EXPECT_FALSE(closestName("colour", kKeys));
  EXPECT_FALSE(closestName("", kKeys));
  EXPECT_FALSE(closestName(std::string(200, 'a'), kKeys));
}

TEST(ClosestName, TheStartOfExactlyOneNameIsThatName) {
  EXPECT_EQ(closestName("samples", kKeys), "samples_per_texel");  // ten edits away, but its only extension
  EXPECT_FALSE(closestName("o", {"output", "outputs"}));          // two extensions, both far
}

TEST(ParseByName, AnUnknownNameListsTheNamesAndSuggestsTheClosest) {
  try {
    parseParameterizationKind("paraboliod");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "parameterization must be one of sphere, paraboloid, cube, latlong; got \"paraboliod\" (did you mean "
              "'paraboloid'?)");
  }
}

}  // namespace
}  // namespace brdfbake
