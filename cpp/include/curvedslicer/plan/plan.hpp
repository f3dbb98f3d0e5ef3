// The deposition plan: the hand-over between path planning (paths/) and positioner
// planning, kinematics and robot programs (robot/, export/), and what the FreeCAD
// workbench stores in a document.
//
// A plan is a sequence of layers, bottom to top; each layer holds its paths in deposition order.
// A path is one weld bead: the arc is on from its first to its last point; between consecutive
// paths (and layers) the torch travels with the arc off. Every quantity is in the part frame
// (the model's original coordinates), lengths in mm.
//
// Plain data, no behaviour beyond small queries; reading and writing the versioned JSON / CSV
// forms lives in plan/plan_io.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "curvedslicer/core/types.hpp"

namespace curvedslicer {

/// One robot point of a path.
struct PathPoint {
  Vec3 position = Vec3::Zero();  ///< mm, part frame, on the layer surface
  /// Unit normal of the layer surface at the point, pointing in the growth direction (towards
  /// increasing geodesic distance, away from the material already deposited).
  Vec3 normal = Vec3::UnitZ();
  /// Unit deposition direction V (paper §3.2): from the wire tip towards the nearest
  /// already-deposited material (previous bead of the layer, previous layer, or the substrate).
  /// The positioner turns the part so that V points along gravity.
  Vec3 deposition = -Vec3::UnitZ();
  /// Bead width at the point, mm (adaptive bead width). 0 means the plan's bead
  /// spacing (plans of format version 1, and every point when adaptive width is off).
  double width = 0.0;
};

/// One weld bead.
struct PlanPath {
  int layer = 0;  ///< index of the layer in Plan::layers (0 = first layer on the start surface)
  int index = 0;  ///< deposition order within the layer, 0-based
  bool closed = false;  ///< a ring: the last point connects back to the first with the arc on
  std::vector<PathPoint> points;  ///< deposition order; at least 2
  double length = 0.0;            ///< mm, arc-on length along the points (incl. closing segment)
  /// s, arc-on dwell at the first point before moving (a spot deposit on a tiny island); 0 = none.
  double dwell = 0.0;
};

/// A patch of a layer no bead covers, for the user to find it.
struct CoverageVoid {
  double area = 0.0;           ///< mm² of layer surface
  Vec3 centre = Vec3::Zero();  ///< mm, part frame, area-weighted centre of the patch
  double size = 0.0;           ///< mm, largest extent of the patch
};

/// How well the beads of one layer cover its surface, measured on the layer surface:
/// a surface point is covered by a bead when it lies within half the bead's width of the bead's
/// centre line (PathPoint::width, or the bead spacing where 0).
struct LayerCoverage {
  bool measured = false;            ///< false: not measured (plans of format version 1, thin walls)
  double area = 0.0;                ///< mm², layer surface area
  double voidShare = 0.0;           ///< [0, 1], share of the area no bead covers
  double overlapShare = 0.0;        ///< [0, 1], share of the area two or more beads cover
  double beadWidth = 0.0;           ///< mm, nominal bead width (the bead spacing)
  std::size_t arcStarts = 0;        ///< paths of the layer (each path is one arc start)
  std::vector<CoverageVoid> voids;  ///< the largest uncovered patches, largest first (at most 10)
};

/// One curved layer and its paths.
struct PlanLayer {
  int index = 0;        ///< 0-based, bottom to top
  double height = 0.0;  ///< geodesic distance of the layer surface from the start surface, mm
  std::string surface;  ///< reference to the layer surface (file name relative to the plan), or ""
  std::vector<PlanPath> paths;        ///< in deposition order
  std::vector<std::string> warnings;  ///< e.g. "no room for a bead", shown to the user
  LayerCoverage coverage;             ///< measured after planning (paths/coverage.hpp)
};

/// Parameters the plan was made with (what a user needs to reproduce it).
struct PlanParameters {
  double layerThickness = 0.0;  ///< h, mm
  double voxelSize = 0.0;       ///< L, mm
  double beadSpacing = 0.0;     ///< s, mm
  double pointSpacing = 0.0;    ///< robot point spacing, mm
  double fitTolerance = 0.0;    ///< spline fit tolerance, mm
  std::string fieldMethod;      ///< volume geodesic method, e.g. "anyangle"
  std::string surfaceMethod;    ///< surface geodesic (GDTC) method
  std::string initialCurve;     ///< how initial curves were chosen, e.g. "boundary"
  /// where paths of one level meet: "centre_bead" | "overlap"; empty for plans that do not
  /// apply it (thin wall, plans written before it existed): then not written to the file
  std::string narrowStrips;
  /// how V was chosen: "growth" | "nearest" (paths/deposition.hpp); empty for plans written
  /// before it existed (their V is the paper's, "nearest"): then not written to the file
  std::string depositionDirection;
  /// degrees: turns sharper than this (within 0.2 mm) were kept as exact corners by the fit;
  /// absent in plans written before it existed (then not written to the file)
  std::optional<double> cornerAngle;
  /// Volume plans only (absent for thin walls and plans written before it existed): mm, the
  /// minimum feature width the planner used (PlannerOptions::minFeatureWidth resolved, > 0)
  std::optional<double> minFeatureWidth;
  /// The bead width range {min, max} as fractions of the bead spacing ({1, 1}: fixed)
  std::optional<std::array<double, 2>> beadWidthRange;
  /// Whether consecutive rings of one region were joined into one arc-on path
  std::optional<bool> connectInsets;
  /// Whether uncovered strips between beads got centre-line fill beads (paths/gap_fill)
  std::optional<bool> fillGaps;
  /// ε, mm, of the layer simplification the layer surfaces went through; absent for
  /// full-resolution layers, thin walls and plans written before it existed
  std::optional<double> layerTolerance;
  /// mm², the smallest uncovered patch gap fill gave a bead (PlannerOptions::minGapArea
  /// resolved, > 0); absent for thin walls and plans written before the option existed
  std::optional<double> minGapArea;
  /// Corner fill: mm, how far a bead's edge may pass the layer boundary at a corner
  /// (PlannerOptions::cornerOverdeposit resolved); < 0: corner fill was off; absent for thin
  /// walls and plans written before corner fill existed (no corner fill)
  std::optional<double> cornerOverdeposit;
  /// Corner fill: degrees, the corners of the layer boundary sharper than this were
  /// filled (PlannerOptions::cornerFillAngle); absent when corner fill was off, for thin walls and
  /// plans written before the option existed
  std::optional<double> cornerFillAngle;
};

struct Plan {
  /// 2: per-point bead width, path dwell, per-layer coverage, bead coverage parameters (version-1
  /// files still read: width = bead spacing, coverage not measured).
  static constexpr int kFormatVersion = 2;
  std::string model;  ///< the model file or document object the plan was made from
  std::string start;  ///< start-surface specification
  PlanParameters parameters;
  std::vector<PlanLayer> layers;

  std::size_t pathCount() const {
    std::size_t n = 0;
    for (const auto& layer : layers) n += layer.paths.size();
    return n;
  }
  std::size_t pointCount() const {
    std::size_t n = 0;
    for (const auto& layer : layers) {
      for (const auto& path : layer.paths) n += path.points.size();
    }
    return n;
  }
};

}  // namespace curvedslicer
