#pragma once
// What a bad fit.json must get: Error(InvalidInput) whose message starts with the file's name and names
// the place (a JSON path, or more of the message).
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <nlohmann/json.hpp>

#include <string>

namespace brdfbake::test {

inline void expectFitFileError(const nlohmann::json& document, const std::string& fragment) {
  try {
    fitFileFromJson(document, "fit.json");
    ADD_FAILURE() << "accepted; expected an error naming " << fragment;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("fit.json: ", 0), 0u) << e.what();
  }
}

}  // namespace brdfbake::test
