// The size of a plan before it is planned: bead paths at spacing s that cover layer
// surfaces of total area A are about A / s long, and robot points every p along them number about
// A / (s·p). A point spacing of 1e-9 mm would ask for ~1e13 points; the check refuses such a run
// with the option value that fits, before any path is fitted or resampled. Cost O(1).
#pragma once

namespace curvedslicer {

/// Peak memory of planning per robot point, bytes: measured on the custom base example
/// (resources/models/custom_base_geom_to_slice.obj, L 0.5, h 1.5, s 3.7), where the peak resident
/// memory of `curvedslicer plan` grew by 128 MB from point spacing 2 mm (17,442 points) to 0.1 mm
/// (304,838 points): 446 bytes per point (points, fitted curves, plan.json and plan.csv text).
inline constexpr double kPlanBytesPerPoint = 450.0;

/// Most robot points a plan may hold, whatever the budget (2^31 - 1).
inline constexpr double kMaxPlanPoints = 2147483647.0;

struct PlanSizeEstimate {
  double pathLength = 0.0;  ///< mm, about the layer area / bead spacing
  double points = 0.0;      ///< robot points, about pathLength / point spacing
  double bytes = 0.0;       ///< points · kPlanBytesPerPoint
};

/// @param layerArea  total area of the layer surfaces (or of a thin wall's surface), mm²
/// @param beadSpacing  s, mm (> 0)
/// @param pointSpacing  p, mm (> 0)
PlanSizeEstimate estimatePlanSize(double layerArea, double beadSpacing, double pointSpacing);

/// Refuses a plan whose estimated memory exceeds the budget, or that would hold more than
/// kMaxPlanPoints points.
/// @param memoryBudgetBytes  bytes; 0 = 80 % of physical memory (as the voxel grid's budget)
/// @throws ResourceLimit naming the estimated points and memory, the budget, and the smallest
///         point spacing (two significant digits) that fits.
void checkPlanSize(double layerArea, double beadSpacing, double pointSpacing,
                   double memoryBudgetBytes);

}  // namespace curvedslicer
