// Constants the test suites share, defined once so that suites compiled together in one unity
// translation unit do not redefine them.
#pragma once

namespace curvedslicer::testing {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDeg = kPi / 180.0;  ///< one degree in radians
inline constexpr double kS = 3.7;            ///< mm, the bead spacing of the paper's example

}  // namespace curvedslicer::testing
