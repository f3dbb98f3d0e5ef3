// Part placement on the table and the table / working-volume check (placement.hpp).
#include "curvedslicer/robot/placement.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

std::string_view toString(PartPlacement placement) {
  return placement == PartPlacement::Cell ? "cell" : "rest";
}

PartPlacement parsePartPlacement(std::string_view name) {
  if (name == "rest") return PartPlacement::Rest;
  if (name == "cell") return PartPlacement::Cell;
  throw InvalidInput("unknown part placement: '" + std::string(name) +
                     "'; choose rest (the part's lowest bead bottom on the table top) or cell "
                     "(the cell's positioner/table_to_part as given)");
}

namespace {

constexpr double kTolerance = 1e-6;  // mm: points this close to a bound are on it

std::string fmt(double value, int precision = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", precision, value);
  return buffer;
}

/// The extreme of one quantity over all weld points, and how many points pass a bound.
struct Extreme {
  double value = -std::numeric_limits<double>::infinity();  ///< largest value seen
  int layer = -1, path = -1, point = -1;
  Vec3 position = Vec3::Zero();  ///< part frame
  std::size_t beyond = 0;        ///< points with value > the bound given to add
  void add(double v, double bound, int l, int p, int k, const Vec3& position) {
    if (v > bound) ++beyond;
    if (v <= value) return;
    value = v;
    layer = l;
    path = p;
    point = k;
    this->position = position;
  }
  bool found() const { return layer >= 0; }
  std::string name() const {
    return "layer " + std::to_string(layer) + " path " + std::to_string(path) + " point " +
           std::to_string(point) + " (part " + fmt(position.x(), 2) + ", " + fmt(position.y(), 2) +
           ", " + fmt(position.z(), 2) + " mm)";
  }
};

/// Calls f(layer, path, point, position in part, position in table) for every plan point.
template <class F>
void forEachWeldPoint(const Plan& plan, const Pose& tableToPart, F&& f) {
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    const auto& paths = plan.layers[l].paths;
    for (std::size_t p = 0; p < paths.size(); ++p) {
      const auto& points = paths[p].points;
      for (std::size_t k = 0; k < points.size(); ++k) {
        const Vec3& x = points[k].position;
        f(static_cast<int>(l), static_cast<int>(p), static_cast<int>(k), x, tableToPart * x);
      }
    }
  }
}

const char* const kHint =
    "set the part's placement on the table: positioner/table_to_part in the cell file, or the "
    "placement rest (--placement rest; Python MotionOptions(placement=\"rest\"); the Job's "
    "PartPlacement Rest)";

}  // namespace

PartPlacementResult placePart(const Plan& plan, const Cell& cell, PartPlacement placement) {
  PartPlacementResult result;
  result.tableToPart = cell.positioner.tableToPart;
  if (placement == PartPlacement::Cell) return result;
  Extreme lowest;  // of -z_table
  forEachWeldPoint(plan, result.tableToPart,
                   [&](int l, int p, int k, const Vec3& part, const Vec3& table) {
                     lowest.add(-table.z(), std::numeric_limits<double>::infinity(), l, p, k, part);
                   });
  if (!lowest.found()) return result;
  const double h = std::max(plan.parameters.layerThickness, 0.0);
  const double bottom = -lowest.value - h;  // table z of the lowest bead bottom
  // A part already resting within kTolerance keeps the cell's placement exactly (no motion
  // changes in the last digits from a lift of 1e-11 mm).
  result.lift = std::abs(bottom) <= kTolerance ? 0.0 : -bottom;
  result.tableToPart.pretranslate(Vec3(0, 0, result.lift));
  result.note =
      "part placement rest: the lowest bead bottom (" + fmt(h) + " mm below " + lowest.name() +
      ") lies on the table top: table_to_part z = " + fmt(result.tableToPart.translation().z()) +
      " mm (the cell gives " + fmt(cell.positioner.tableToPart.translation().z()) +
      " mm); use --placement cell to keep the cell's placement";
  return result;
}

void checkPartPlacement(const Plan& plan, const PositionerDescription& positioner) {
  const PositionerGeometry& g = positioner.geometry;
  Extreme below, outside, above;  // of -z, radius, z (table frame)
  forEachWeldPoint(
      plan, positioner.tableToPart, [&](int l, int p, int k, const Vec3& part, const Vec3& table) {
        below.add(-table.z(), kTolerance, l, p, k, part);
        outside.add(std::hypot(table.x(), table.y()), g.maxPartRadius + kTolerance, l, p, k, part);
        above.add(table.z(), g.maxPartHeight + kTolerance, l, p, k, part);
      });
  if (below.beyond > 0) {
    throw InvalidInput("weld points below the table top: " + below.name() + " lies " +
                       fmt(below.value) + " mm below the table (" + std::to_string(below.beyond) +
                       " points below it); " + kHint);
  }
  if (outside.beyond > 0) {
    throw InvalidInput("weld points outside the positioner's working volume: " + outside.name() +
                       " lies " + fmt(outside.value) + " mm from the rotation axis, " +
                       fmt(outside.value - g.maxPartRadius) + " mm beyond its radius of " +
                       fmt(g.maxPartRadius, 1) + " mm (" + std::to_string(outside.beyond) +
                       " points beyond it); " + kHint +
                       " (the part's xy), or give the cell's positioner/geometry");
  }
  if (above.beyond > 0) {
    throw InvalidInput("weld points above the positioner's working volume: " + above.name() +
                       " lies " + fmt(above.value) + " mm above the table, " +
                       fmt(above.value - g.maxPartHeight) + " mm above its height of " +
                       fmt(g.maxPartHeight, 1) + " mm (" + std::to_string(above.beyond) +
                       " points above it); " + kHint + ", or give the cell's positioner/geometry");
  }
}

}  // namespace curvedslicer
