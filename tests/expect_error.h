// Fails(result, code, {"part", ...}): the result failed with `code` and a message containing every
// part; on failure the assertion shows the whole message. Use as EXPECT_TRUE(Fails(...)).
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "core/base/result.h"

namespace cagewrap {

template <class R>
::testing::AssertionResult Fails(const R& r, ErrorCode code, std::initializer_list<std::string> parts) {
  if (r.ok()) return ::testing::AssertionFailure() << "succeeded; expected " << error_code_name(code);
  std::string problems;
  if (r.error().code != code)
    problems += std::string("code ") + error_code_name(r.error().code) + " instead of " + error_code_name(code) + "; ";
  for (const auto& part : parts)
    if (r.error().message.find(part) == std::string::npos) problems += "no \"" + part + "\" in the message; ";
  if (problems.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << problems << "message: \"" << r.error().message << "\"";
}

}  // namespace cagewrap
