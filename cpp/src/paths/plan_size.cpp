#include "curvedslicer/paths/plan_size.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer {

namespace {

std::string formatGeneral(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
  return buffer;
}

/// 1,234,567 up to 1e15, then 1.2e+18.
std::string formatCount(double value) {
  if (!(value < 1e15)) return formatGeneral(value, 2);
  const std::string digits = std::to_string(static_cast<long long>(std::llround(value)));
  std::string grouped;
  for (std::size_t n = 0; n < digits.size(); ++n) {
    if (n > 0 && (digits.size() - n) % 3 == 0) grouped += ',';
    grouped += digits[n];
  }
  return grouped;
}

std::string formatMemory(double bytes) {
  char buffer[64];
  if (!(bytes < 1e15)) {
    std::snprintf(buffer, sizeof(buffer), "%.1e bytes", bytes);
  } else if (bytes >= 1e9) {
    std::snprintf(buffer, sizeof(buffer), "%.1f GB", bytes / 1e9);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.1f MB", bytes / 1e6);
  }
  return buffer;
}

/// Smallest value with two significant digits that is >= `value`.
double roundUpTwoDigits(double value) {
  const double step = std::pow(10.0, std::floor(std::log10(value)) - 1.0);
  return std::ceil(value / step * (1.0 - 1e-12)) * step;
}

}  // namespace

PlanSizeEstimate estimatePlanSize(double layerArea, double beadSpacing, double pointSpacing) {
  PlanSizeEstimate e;
  e.pathLength = std::max(0.0, layerArea) / beadSpacing;
  e.points = e.pathLength / pointSpacing;
  e.bytes = e.points * kPlanBytesPerPoint;
  return e;
}

void checkPlanSize(double layerArea, double beadSpacing, double pointSpacing,
                   double memoryBudgetBytes) {
  if (!(beadSpacing > 0.0) || !(pointSpacing > 0.0)) return;  // the option checks report these
  const PlanSizeEstimate e = estimatePlanSize(layerArea, beadSpacing, pointSpacing);
  double budget = memoryBudgetBytes;
  if (!(budget > 0.0)) {
    const double physical = physicalMemoryBytes();
    budget = physical > 0.0 ? 0.8 * physical : 4e9;  // as the voxel grid's budget
  }
  // Point indices are 32-bit in motion plans and exports: a larger budget does not help there.
  const double limit = std::min(budget, kMaxPlanPoints * kPlanBytesPerPoint);
  if (!(e.bytes > limit)) return;  // also for a non-finite area: the model checks report it
  const double fitting = roundUpTwoDigits(pointSpacing * e.bytes / limit);
  throw ResourceLimit("the plan would hold about " + formatCount(e.points) + " robot points (" +
                      formatCount(e.pathLength) + " mm of bead paths at a point spacing of " +
                      formatGeneral(pointSpacing, 4) + " mm) and need about " +
                      formatMemory(e.bytes) + " at " + formatGeneral(kPlanBytesPerPoint, 3) +
                      " bytes per point, over the memory budget of " + formatMemory(budget) +
                      (budget > limit ? " (or over the limit of 2,147,483,647 points)" : "") +
                      "; use a point spacing of at least " + formatGeneral(fitting, 2) +
                      " mm (or a larger bead spacing)" +
                      (budget > limit ? "" : " or raise the memory budget"));
}

}  // namespace curvedslicer
