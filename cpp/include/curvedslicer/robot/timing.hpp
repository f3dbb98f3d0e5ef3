// Time parameterisation of a planned motion against every axis's speed limit: each
// move (from one motion point to the next) takes the longest of
//   - its nominal time: a weld move's part-frame length / the cell's weld speed (the speed
//     relative to the part), an arc-off move's length / the travel speed (the longer of its
//     part-frame and world TCP lengths),
//   - |Δq_j| / maxSpeed_j for each of the six robot joints,
//   - |Δa1| / tilt maxSpeed and |Δa2| / rotation maxSpeed of the positioner,
// i.e. all axes move together, linearly interpolated, and the slowest sets the pace (no
// acceleration limits: the cell description has none). Where an axis makes a weld move slower
// than nominal, the weld speed drops: MotionPoint::speed holds the lower speed and the point is
// flagged kMotionSpeedReduced; consecutive reduced moves of a path become one SpeedReduction.
// Dwells (process pathDwell after every path, layerDwell after every layer's last path) are
// waits at the path end before the next move. A layer whose time, from the arrival at its first
// weld point to the end of the dwells after its last path, is below the process's minLayerTime
// waits the rest there too (MotionEstimate::coolingWait of that layer; not the last layer welded,
// onto which nothing is deposited). MotionPoint::time is the arrival time.
// Estimates: per layer and in total, arcTime = the weld moves' times, travelTime = the arc-off
// moves' times (a move counts for the layer of its end point), dwellTime = the dwells, and
// totalTime = their sum = the last point's time + the dwell after it (to rounding); wireLength,
// depositedVolume and depositedMass follow from the wire feed over arcTime.
// Preconditions: MotionPlan::paths spans are valid and layers has one entry per plan layer.
// Cost: O(points), a few tens of nanoseconds per point.
#pragma once

#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

struct TimingOptions {
  /// false: nominal times only (weld and travel speeds), no axis limits
  bool limitAxes = true;
};

/// Sets MotionPoint::time and ::speed, kMotionSpeedReduced, MotionPlan::speedReductions, the
/// time fields of MotionPlan::layers and ::total (see above), and appends one warning that
/// summarises the speed reductions. `motion.layers` must already hold one entry per plan layer
/// (bead length, paths, points as estimatePlan gives them).
void parameteriseTime(MotionPlan& motion, const Cell& cell, const TimingOptions& options = {});

/// The name of a limiting axis as SpeedReduction::axis gives it: "robot joint 1".."robot joint
/// 6" for 0..5, "positioner tilt (a1)" for 6, "positioner rotation (a2)" for 7, "weld speed"
/// (nominal) for 8.
std::string_view axisName(int axis);

}  // namespace curvedslicer
