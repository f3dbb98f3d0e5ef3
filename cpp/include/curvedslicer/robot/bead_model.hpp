// The bead model of a GMA deposition process: measured single-bead width and
// height over a grid of wire feed speed (WFS, m/min) × travel speed (TS, mm/s), interpolated
// bilinearly; and its inverse, the WFS and TS that give a wanted width at a wanted height (the
// layer thickness). In GMA deposition both width and height follow WFS and TS, so changing TS
// alone to change the width would change the layer height too.
//
// Table: rows = wire feeds (ascending), columns = travel speeds (ascending), at least 2 × 2;
// every width and height positive. Evaluation outside the table clamps WFS and TS to its range.
// Inverse: on every cell, Newton's method on the bilinear 2 × 2 system (u, v) ↦ (width, height)
// kept inside the cell; the cell whose solution has the least relative error wins (first cell on
// ties). Within a cell the map is one-to-one when width and height are monotone along the grid
// lines the usual way (width up with WFS and down with TS); where no cell reaches the wanted pair
// the result is the closest table point found, `reached` false, and its shortfall is the
// difference. Cost: O(cells) per inversion.
#pragma once

#include <string>
#include <vector>

namespace curvedslicer {

struct BeadModel {
  std::vector<double> wireFeeds;            ///< m/min, grid rows, strictly ascending
  std::vector<double> travelSpeeds;         ///< mm/s, grid columns, strictly ascending
  std::vector<std::vector<double>> width;   ///< mm, width[row][column], single bead
  std::vector<std::vector<double>> height;  ///< mm, height[row][column], single bead
  std::string source;                       ///< where the numbers come from (free text)
  bool empty() const { return wireFeeds.empty(); }
};

/// Width and height of a bead, mm.
struct BeadGeometry {
  double width = 0.0;
  double height = 0.0;
};

/// What the inverse picked.
struct BeadSetting {
  double wireFeed = 0.0;     ///< m/min
  double travelSpeed = 0.0;  ///< mm/s
  BeadGeometry achieved;     ///< the model's width and height there
  bool reached = false;      ///< both within `BeadModelOptions::tolerance` of the wanted ones
};

/// Checks the table. @throws InvalidInput naming the cell field (JSON path under
/// /process/bead_model), e.g. "width_mm has 3 rows, expected 4 (one per wire feed)".
void validateBeadModel(const BeadModel& model);

/// Bilinear width and height at (wireFeed m/min, travelSpeed mm/s), clamped to the table.
BeadGeometry evaluateBeadModel(const BeadModel& model, double wireFeed, double travelSpeed);

/// The WFS and TS for a bead `width` mm wide and `height` mm high (see the file comment).
/// @param tolerance  mm, largest width or height error that counts as reached
/// @throws InvalidInput for a non-positive or non-finite width or height.
BeadSetting solveBeadSetting(const BeadModel& model, double width, double height,
                             double tolerance = 1e-3);

}  // namespace curvedslicer
