// Whole-model tests that take minutes in Release take 5-20 times as long under AddressSanitizer +
// UndefinedBehaviorSanitizer (scripts/run_tests.sh, build-asan/). Those tests skip themselves in
// the sanitizer build, naming the smaller test that runs the same code there; the Release build
// runs them in full.
#pragma once

#include <gtest/gtest.h>

#ifdef CURVEDSLICER_SANITIZED_BUILD
#define CURVEDSLICER_SKIP_IF_SANITIZED(coveredBy)                                             \
  GTEST_SKIP() << "whole-model test, too slow under sanitizers (runs in the Release build); " \
                  "the same code runs here in "                                               \
               << (coveredBy)
#else
#define CURVEDSLICER_SKIP_IF_SANITIZED(coveredBy) static_cast<void>(0)
#endif

namespace curvedslicer::testing {

/// True in the sanitizer build: a suite's shared set-up can then skip its whole-model work.
constexpr bool sanitizedBuild() {
#ifdef CURVEDSLICER_SANITIZED_BUILD
  return true;
#else
  return false;
#endif
}

}  // namespace curvedslicer::testing
