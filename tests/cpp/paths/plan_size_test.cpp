// The plan's size is estimated from the layer area before planning: paths of spacing s
// over an area A are A/s long, with a robot point every p; a run that would not fit the memory
// budget is refused with the point spacing that fits.
#include "curvedslicer/paths/plan_size.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

TEST(PlanSize, EstimateIsAreaOverBeadSpacingOverPointSpacing) {
  const PlanSizeEstimate e = estimatePlanSize(1000.0, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(e.pathLength, 500.0);
  EXPECT_DOUBLE_EQ(e.points, 1000.0);
  EXPECT_DOUBLE_EQ(e.bytes, 1000.0 * kPlanBytesPerPoint);
}

TEST(PlanSize, WithinTheBudgetPassesBeyondItNamesThePointSpacingThatFits) {
  EXPECT_NO_THROW(checkPlanSize(1000.0, 2.0, 0.5, 1000.0 * kPlanBytesPerPoint));
  try {
    checkPlanSize(1000.0, 2.0, 0.5, 100.0 * kPlanBytesPerPoint);  // ten times too small
    ADD_FAILURE() << "a plan ten times over the budget was accepted";
  } catch (const ResourceLimit& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("the plan would hold about 1,000 robot points (500 mm of bead paths "
                           "at a point spacing of 0.5 mm)"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("use a point spacing of at least 5 mm"), std::string::npos) << message;
  }
  // The suggested spacing fits.
  EXPECT_NO_THROW(checkPlanSize(1000.0, 2.0, 5.0, 100.0 * kPlanBytesPerPoint));
}

TEST(PlanSize, NanometrePointSpacingIsRefusedAtOnceUnderTheAutomaticBudget) {
  const auto begin = std::chrono::steady_clock::now();
  EXPECT_THROW(checkPlanSize(2.0e5, 3.7, 1e-9, 0.0), ResourceLimit);
  EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::seconds(1));
  // Beyond 2^31 points a larger budget does not help.
  try {
    checkPlanSize(2.0e5, 3.7, 1e-9, 1e36);
    ADD_FAILURE() << "22 trillion points were accepted under a budget of 1e36 bytes";
  } catch (const ResourceLimit& e) {
    EXPECT_NE(std::string(e.what()).find("(or over the limit of 2,147,483,647 points)"),
              std::string::npos)
        << e.what();
  }
  // Bad spacings are left to the option checks (their own messages).
  EXPECT_NO_THROW(checkPlanSize(2.0e5, 0.0, 1e-9, 0.0));
  EXPECT_NO_THROW(checkPlanSize(2.0e5, 3.7, -1.0, 0.0));
}

}  // namespace
}  // namespace curvedslicer
