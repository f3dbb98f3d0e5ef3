// Neutral per-point output of a motion plan: CSV (one row per motion point) or JSON (the same
// rows plus the cell name, units and a ROS-style joint trajectory view: joint names and time from
// start).
//
// Columns (both forms): layer, path, index, x_mm, y_mm, z_mm (part frame), nx, ny, nz (layer
// normal), vx, vy, vz (deposition direction V of the plan), a1_deg, a2_deg (positioner, model
// convention), j1_deg … j6_deg (robot, controller convention), speed_mm_s, arc_on (0/1),
// path_start, path_end (0/1), time_s (MotionPoint::time: arrival time from the program start of
// the time-parameterised motion, dwells included), residual_deg, flags (MotionFlag bits),
// wire_feed_m_min (of the move arriving at the point: MotionPoint::wireFeed, or the cell's
// process wire feed where that is 0; 0 with the arc off), weld_schedule (MotionPoint::
// weldSchedule, 0 = the cell's), bead_width_mm (MotionPoint::beadWidth), torch_angle_deg,
// travel_angle_deg (push > 0, drag < 0), work_angle_deg (MotionPoint: the torch off gravity to
// clear the deposit, table or fixture), gravity_deviation_deg (MotionPoint::residual: the deposit
// off gravity), kind (path | retract | travel | approach | home). Every motion point is a row,
// arc-off points included, so axis speeds follow from consecutive rows' joints, a1, a2 and time_s.
// Numbers in the shortest form that reads back to the same double; CSV with '\n' line endings and a
// header row. Version 4 (version 3 had no torch angles and gravity deviation; version 2 no wire
// feed, weld schedule and bead width; version 1 no kind and a distance / speed time). JSON:
// {"format": "curvedslicer-motion", "version": 4, "cell": …, "columns": […],
//        "joint_names": ["j1",…,"j6","a1","a2"], "points": [[…, "path"], …]} (kind as a string).
// Cost: O(points), about 300 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class NeutralWriter final : public ProgramExporter {
 public:
  /// @param format  ExportFormat::Csv or ExportFormat::Json
  explicit NeutralWriter(ExportFormat format) : format_(format) {}
  ExportFormat format() const override { return format_; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;

 private:
  ExportFormat format_;
};

}  // namespace curvedslicer
