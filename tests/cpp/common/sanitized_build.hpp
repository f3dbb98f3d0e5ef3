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

/// Factor on the grid, layer and bead sizes of the tests' coarse whole-part runs (the 200 mm box
/// at voxel 5 mm): under the sanitizers the same stages run 10-20 times slower, so there those
/// runs take a twice coarser grid; what they check does not depend on the scale.
constexpr double coarseningUnderSanitizers() {
  return sanitizedBuild() ? 2.0 : 1.0;
}

}  // namespace curvedslicer::testing
