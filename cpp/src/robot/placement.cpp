// Part placement on the table and the table / working-volume check (placement.hpp).
#include "curvedslicer/robot/placement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

std::string_view toString(PartPlacement placement) {
  switch (placement) {
    case PartPlacement::Cell:
      return "cell";
    case PartPlacement::Auto:
      return "auto";
    default:
      return "rest";
  }
}

PartPlacement parsePartPlacement(std::string_view name) {
  if (name == "rest") return PartPlacement::Rest;
  if (name == "cell") return PartPlacement::Cell;
  if (name == "auto") return PartPlacement::Auto;
  throw InvalidInput("unknown part placement: '" + std::string(name) +
                     "'; choose rest (the part's lowest bead bottom on the fixture's top, or the "
                     "table's), cell (the cell's positioner/table_to_part as given) or auto (rest "
                     "on the lowest riser that keeps the torch clear of the table)");
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
  void add(double v, double bound, int l, int p, int k, const Vec3& where) {
    if (v > bound) ++beyond;
    if (v <= value) return;
    value = v;
    layer = l;
    path = p;
    point = k;
    position = where;
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

/// How far below the weld point (table z, mm) its bead reaches: the bead's cross-section is
/// the rectangle {p - a·n + b·w : a in [0, h], b in [-s/2, s/2]} with n the layer normal and
/// w = t × n across the path (t the path tangent), all in the table frame. Where the tangent is
/// undefined (repeated points) w is taken as steep as n allows (the conservative bound).
double beadDepthBelow(const PlanPath& path, std::size_t k, const Mat3& rotation, double h,
                      double s) {
  const auto& points = path.points;
  const std::size_t n = points.size();
  const std::size_t prev = k > 0 ? k - 1 : (path.closed ? n - 1 : 0);
  const std::size_t next = k + 1 < n ? k + 1 : (path.closed ? 0 : n - 1);
  const Vec3 normal = rotation * points[k].normal.normalized();
  const Vec3 tangent = rotation * (points[next].position - points[prev].position);
  const Vec3 across = tangent.cross(normal);
  const double steepest = std::sqrt(std::max(0.0, 1.0 - normal.z() * normal.z()));
  const double acrossZ = across.norm() > 1e-9 * std::max(tangent.norm(), 1e-300)
                             ? std::abs(across.normalized().z())
                             : steepest;
  return h * std::max(normal.z(), 0.0) + 0.5 * s * acrossZ;
}

/// "the table top" / "the substrate plate's top (z = 42.000 mm above the table)" …
std::string supportName(const Cell& cell) {
  const FixtureGeometry& f = cell.positioner.fixture;
  if (f.hasSubstrate()) {
    return "the substrate plate's top (" + fmt(f.top()) + " mm above the table" +
           (f.hasRiser() ? ", on a riser of " + fmt(f.riserHeight) + " mm)" : ")");
  }
  if (f.hasRiser()) return "the riser's top (" + fmt(f.top()) + " mm above the table)";
  return "the table top";
}

const char* const kHint =
    "set the part's placement on the table: positioner/table_to_part in the cell file, or the "
    "placement rest (--placement rest; Python MotionOptions(placement=\"rest\"); the Job's "
    "PartPlacement Rest)";

}  // namespace

namespace {

/// Mean deposition direction V of the first layer with points (part frame, unit), or zero.
Vec3 startDirection(const Plan& plan) {
  for (const PlanLayer& layer : plan.layers) {
    Vec3 sum = Vec3::Zero();
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& point : path.points) sum += point.deposition;
    }
    if (sum.norm() > 1e-9) return sum.normalized();
  }
  return Vec3::Zero();
}

/// Rest, first step: a part whose first layer is deposited more than 30° away from straight
/// down onto the table (its start surface faces sideways: the torch would lie across the table) (a
/// start surface on the part's side or tilted) is turned by the smallest rotation that makes it so
/// — the start surface faces the table, as the substrate does — and its points are centred on the
/// rotation axis. Returns the note, or "".
std::string faceStartSurfaceDown(const Plan& plan, Pose& tableToPart) {
  constexpr double kStartTilt = 30.0 * 3.14159265358979323846 / 180.0;
  const Vec3 v = startDirection(plan);
  if (v.isZero()) return "";
  const Vec3 down = -Vec3::UnitZ();
  const Vec3 vTable = tableToPart.linear() * v;
  const double tilt = std::atan2(vTable.cross(down).norm(), vTable.dot(down));
  if (tilt <= kStartTilt) return "";
  tableToPart.prerotate(Eigen::Quaterniond::FromTwoVectors(vTable, down).toRotationMatrix());
  Eigen::AlignedBox3d box;
  forEachWeldPoint(plan, tableToPart,
                   [&](int, int, int, const Vec3&, const Vec3& inTable) { box.extend(inTable); });
  tableToPart.pretranslate(Vec3(-box.center().x(), -box.center().y(), 0.0));
  const std::string degrees = fmt(tilt * 180.0 / 3.14159265358979323846, 1);
  return "part placement rest: the first layer is deposited " + degrees +
         " deg away from straight down onto the table, so the part is turned by " + degrees +
         " deg to put its start surface on the table and centred on the rotation axis; ";
}

}  // namespace

PartPlacementResult placePart(const Plan& plan, const Cell& cell, PartPlacement placement) {
  PartPlacementResult result;
  result.tableToPart = cell.positioner.tableToPart;
  if (placement == PartPlacement::Cell) return result;  // Auto: as Rest on the cell's fixture
  const std::string turned = faceStartSurfaceDown(plan, result.tableToPart);
  // The lowest bead bottom: of -(z_table - depth of the bead below the point).
  const double h = std::max(plan.parameters.layerThickness, 0.0);
  const double s = std::max(plan.parameters.beadSpacing, 0.0);
  const Mat3 rotation = result.tableToPart.rotation();
  Extreme lowest;
  double depth = 0.0;  // of the lowest bead below its weld point
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    const auto& paths = plan.layers[l].paths;
    for (std::size_t p = 0; p < paths.size(); ++p) {
      for (std::size_t k = 0; k < paths[p].points.size(); ++k) {
        const Vec3& x = paths[p].points[k].position;
        const double d = beadDepthBelow(paths[p], k, rotation, h, s);
        const double before = lowest.value;
        lowest.add(-((result.tableToPart * x).z() - d), std::numeric_limits<double>::infinity(),
                   static_cast<int>(l), static_cast<int>(p), static_cast<int>(k), x);
        if (lowest.value != before) depth = d;
      }
    }
  }
  if (!lowest.found()) return result;
  const double bottom = -lowest.value;  // table z of the lowest bead bottom
  const double support = cell.positioner.fixture.top();
  // A part already resting within kTolerance keeps the cell's placement exactly (no motion
  // changes in the last digits from a lift of 1e-11 mm).
  result.lift = std::abs(bottom - support) <= kTolerance ? 0.0 : support - bottom;
  result.tableToPart.pretranslate(Vec3(0, 0, result.lift));
  result.note = turned + "part placement rest: the lowest bead bottom (" + fmt(depth) +
                " mm below " + lowest.name() + ") lies on " + supportName(cell) +
                ": table_to_part z = " + fmt(result.tableToPart.translation().z()) +
                " mm (the cell gives " + fmt(cell.positioner.tableToPart.translation().z()) +
                " mm); use --placement cell to keep the cell's placement";
  return result;
}

double riserDiameterFor(const Plan& plan, const Cell& cell, const Pose& tableToPart) {
  const FixtureGeometry& f = cell.positioner.fixture;
  if (f.riserDiameter > 0.0) return f.riserDiameter;
  if (f.substrateSize > 0.0) return f.substrateSize;
  double radius = 0.0;
  for (const PlanLayer& layer : plan.layers) {
    bool any = false;
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& point : path.points) {
        const Vec3 x = tableToPart * point.position;
        radius = std::max(radius, std::hypot(x.x(), x.y()));
        any = true;
      }
    }
    if (any) break;
  }
  const double bead = std::max(plan.parameters.beadSpacing, 0.0);
  return std::min(2.0 * radius + bead, 2.0 * cell.positioner.geometry.tableRadius);
}

double supportDiameterFor(const Plan& plan, const Pose& tableToPart) {
  for (const PlanLayer& layer : plan.layers) {
    double lowest = kInf;
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& point : path.points) {
        lowest = std::min(lowest, (tableToPart * point.position).z());
      }
    }
    if (!(lowest < kInf)) continue;
    const double reach = std::max(plan.parameters.layerThickness, 0.0) + 1e-9;
    double radius = 0.0;
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& point : path.points) {
        const Vec3 x = tableToPart * point.position;
        if (x.z() <= lowest + reach) radius = std::max(radius, std::hypot(x.x(), x.y()));
      }
    }
    return 2.0 * radius + std::max(plan.parameters.beadSpacing, 0.0);
  }
  return 0.0;
}

Cell withPartPlacement(Cell cell, const Pose& tableToPart) {
  cell.positioner.tableToPart = tableToPart;
  return cell;
}

void checkPartPlacement(const Plan& plan, const PositionerDescription& positioner) {
  const PositionerGeometry& g = positioner.geometry;
  const double support = positioner.fixture.top();
  Extreme below, outside, above;  // of support - z, radius, z (table frame)
  forEachWeldPoint(
      plan, positioner.tableToPart, [&](int l, int p, int k, const Vec3& part, const Vec3& table) {
        below.add(support - table.z(), kTolerance, l, p, k, part);
        outside.add(std::hypot(table.x(), table.y()), g.maxPartRadius + kTolerance, l, p, k, part);
        above.add(table.z(), g.maxPartHeight + kTolerance, l, p, k, part);
      });
  if (below.beyond > 0) {
    const bool fixture = support > 0.0;
    const std::string surface = fixture ? "the fixture's top (" + fmt(support) +
                                              " mm above the table: riser and substrate plate)"
                                        : "the table top";
    throw InvalidInput("weld points below " + surface + ": " + below.name() + " lies " +
                       fmt(below.value) + " mm below the " + (fixture ? "fixture's top" : "table") +
                       " (" + std::to_string(below.beyond) + " points below it); " + kHint);
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
