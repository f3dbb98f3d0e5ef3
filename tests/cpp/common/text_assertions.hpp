// Assertions on text shared by the suites that check messages and program output.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace curvedslicer::testing {

/// Success when `part` occurs in `text`; the failure message quotes both.
inline ::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

}  // namespace curvedslicer::testing
