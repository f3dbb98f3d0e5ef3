// Contour-parallel paths from a layer's boundary: a rectangular layer and a
// layer with a hole. No self-intersection, neighbouring paths never closer than 0.95·s — including
// a path against itself (points more than π·s/2 apart along it, so the opposite side of a thin
// loop counts but the neighbours on a tight curve do not) and paths of the same level —, the strip
// between the outermost path and the boundary at most s/2 + fit tolerance, fits within tolerance.
// The paths go through resolveNarrowStrips, the planner's own rule where the fronts meet; the
// cases include widths where they meet awkwardly (a leftover strip of 2.7 mm and of 0.2 mm at
// s = 3.7, a hole whose front meets the rim's all round, an eccentric hole).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/iso_lines.hpp"
#include "curvedslicer/paths/narrow_strips.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/paths/surface_curves.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"
#include "paths/joined_paths.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::makeRectangleMesh;
using testing::makeRevolutionMesh;
using testing::Profile;

/// Smallest distance between points of `path` more than `exclusion` apart along it, mm (the path
/// densified to 0.1 mm; brute force).
double computeSelfClearance(const Polyline& path, double exclusion) {
  const Polyline dense = resamplePolyline(path, 0.1);
  const std::vector<double> arc = computeCumulativeLengths(dense);
  const double length = dense.length();
  double closest = kInf;
  for (std::size_t i = 0; i < dense.points.size(); ++i) {
    for (std::size_t j = i + 1; j < dense.points.size(); ++j) {
      double along = arc[j] - arc[i];
      if (dense.closed) along = std::min(along, length - along);
      if (along <= exclusion) continue;
      closest = std::min(closest, (dense.points[i] - dense.points[j]).norm());
    }
  }
  return closest;
}

struct Clearance {
  double self = kInf, sameLevel = kInf, nextLevel = kInf;
  double all() const { return std::min({self, sameLevel, nextLevel}); }
};

/// Clearances of fitted paths, per level.
Clearance measureClearance(const std::vector<std::vector<Polyline>>& levels, double s) {
  Clearance c;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    for (std::size_t i = 0; i < levels[k].size(); ++i) {
      const Polyline& path = levels[k][i];
      c.self = std::min(c.self, computeSelfClearance(path, 0.5 * std::numbers::pi * s));
      for (std::size_t j = i + 1; j < levels[k].size(); ++j) {
        c.sameLevel = std::min(c.sameLevel, computePolylineDistance(path, levels[k][j]));
      }
      if (k + 1 < levels.size()) {
        for (const Polyline& next : levels[k + 1]) {
          c.nextLevel = std::min(c.nextLevel, computePolylineDistance(path, next));
        }
      }
    }
  }
  return c;
}

struct ContourCase {
  NarrowStripResult strips;
  std::vector<std::vector<Polyline>> fitted;  // after the rule
  Clearance before, after;
};

ContourCase checkContourParallel(const TriMesh& layer, double s, const std::string& name) {
  SCOPED_TRACE(name);
  ContourCase out;
  const PathFitOptions fitOptions;  // 0.05 mm, 2 mm
  const std::vector<Polyline> boundary = extractBoundaryLoops(layer);
  EXPECT_FALSE(boundary.empty());
  const SurfaceGeodesicResult field = computeSurfaceGeodesic(layer, boundary);
  double maxDistance = 0.0;
  for (const double d : field.distance) maxDistance = std::max(maxDistance, d);
  NarrowStripOptions rule;  // the planner's rule, with the planner's margin (2 × fit tolerance)
  rule.margin = 2.0 * fitOptions.tolerance;
  std::vector<std::vector<Polyline>> raw, innerEdges;
  std::vector<double> values;
  for (const double value : computeIsoValues(s, maxDistance, IsoValueStart::Boundary)) {
    std::vector<Polyline> lines = extractIsoLines(field.mesh, field.distance, value);
    if (lines.empty()) continue;
    raw.push_back(std::move(lines));
    values.push_back(value);
    innerEdges.push_back(
        extractIsoLines(field.mesh, field.distance, value + 0.5 * s + rule.innerEdgeOffset));
  }
  EXPECT_GE(raw.size(), 3u);
  const auto fitAll = [&](const std::vector<std::vector<Polyline>>& levels, bool check) {
    std::vector<std::vector<Polyline>> fitted(levels.size());
    for (std::size_t k = 0; k < levels.size(); ++k) {
      for (const Polyline& line : levels[k]) {
        const PathFitResult fit = fitPath(line, fitOptions);
        if (check) {
          EXPECT_LE(fit.fitDeviation, fitOptions.tolerance);
          EXPECT_LE(fit.chordError, fitOptions.tolerance);
          // Independent check: resampled path within fit + chord tolerance of the raw line.
          EXPECT_LE(computeOneSidedHausdorff(fit.points, line, 4),
                    fitOptions.tolerance + fitOptions.tolerance + 1e-9);
          EXPECT_EQ(fit.points.closed, line.closed);
          EXPECT_FALSE(hasSelfIntersection(fit.points, 1e-6)) << "level " << k;
        }
        fitted[k].push_back(fit.points);
      }
    }
    return fitted;
  };
  out.before = measureClearance(fitAll(raw, false), s);

  out.strips = resolveNarrowStrips(raw, values, s, rule, innerEdges);
  out.fitted = fitAll(out.strips.levels, true);
  out.after = measureClearance(out.fitted, s);

  int paths = 0;
  for (const auto& level : out.fitted) paths += static_cast<int>(level.size());
  // Strip: every point of the outermost paths (not centre beads) to the nearest boundary.
  double widestStrip = 0.0, narrowestStrip = kInf;
  for (std::size_t i = 0; i < out.fitted[0].size(); ++i) {
    if (out.strips.centreBead[0][i]) continue;
    for (const Vec3& p : out.fitted[0][i].points) {
      double d = kInf;
      for (const Polyline& b : boundary) d = std::min(d, closestPointOnPolyline(b, p).distance);
      widestStrip = std::max(widestStrip, d);
      narrowestStrip = std::min(narrowestStrip, d);
    }
  }
  std::cout << name << ": " << out.fitted.size() << " levels, " << paths << " paths ("
            << out.strips.centreBeads << " centre beads, " << out.strips.droppedCentreBeads
            << " dropped, " << out.strips.shortenedEnds << " ends shortened); closest before "
            << out.before.all() << " mm (self " << out.before.self << ", same level "
            << out.before.sameLevel << "), after " << out.after.all() << " mm (self "
            << out.after.self << ", same level " << out.after.sameLevel << ", next level "
            << out.after.nextLevel << "), s = " << s << "; strip " << narrowestStrip << " .. "
            << widestStrip << " mm\n";
  for (const std::string& w : out.strips.warnings) std::cout << "  " << w << "\n";
  EXPECT_GE(out.after.all(), 0.95 * s);
  EXPECT_LE(widestStrip, s / 2 + fitOptions.tolerance);
  EXPECT_GE(narrowestStrip, s / 2 - fitOptions.tolerance);
  // Nothing replaced silently: a centre bead or a drop always has its warning.
  EXPECT_GE(out.strips.warnings.size(), out.strips.centreBeads + out.strips.droppedCentreBeads);
  return out;
}

/// The single centre bead of a rectangle 60 mm long: along y = yMid from x ≈ xEnd to 60 − xEnd;
/// every other path a closed ring.
void expectCentreBeadOnMidline(const ContourCase& r, double yMid, double xEnd) {
  ASSERT_EQ(r.strips.centreBeads, 1u);
  int rings = 0, beads = 0;
  for (std::size_t k = 0; k < r.fitted.size(); ++k) {
    for (std::size_t i = 0; i < r.fitted[k].size(); ++i) {
      const Polyline& path = r.fitted[k][i];
      if (!r.strips.centreBead[k][i]) {
        EXPECT_TRUE(path.closed) << "level " << k;
        ++rings;
        continue;
      }
      ++beads;
      EXPECT_FALSE(path.closed);
      double xMin = kInf, xMax = -kInf;
      for (const Vec3& p : path.points) {
        EXPECT_NEAR(p.y(), yMid, 0.1);
        xMin = std::min(xMin, p.x());
        xMax = std::max(xMax, p.x());
      }
      EXPECT_NEAR(xMin, xEnd, 0.3);
      EXPECT_NEAR(xMax, 60.0 - xEnd, 0.3);
    }
  }
  EXPECT_EQ(beads, 1);
  EXPECT_EQ(rings, static_cast<int>(r.fitted.size()) - (r.fitted.back().size() == 1 ? 1 : 0));
}

bool warnsAbout(const ContourCase& r, const std::string& text) {
  for (const std::string& w : r.strips.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(ContourPaths, RectangularLayer) {
  // 60 x 40 at s = 3.7: rings at 1.85 … 16.65 mm; the ridge is at 20 mm, so a strip 3.0 mm wide
  // is left beyond the last ring's inner edge (18.5 mm). A bead there would be 3.35 mm from the
  // last ring, under 0.95·s: the strip is left empty and reported.
  const ContourCase r =
      checkContourParallel(makeRectangleMesh(0, 60, 0, 40, 120, 80), 3.7, "rectangle 60 x 40");
  EXPECT_EQ(r.strips.centreBeads, 0u);
  EXPECT_EQ(r.strips.droppedCentreBeads, 1u);
  EXPECT_TRUE(warnsAbout(r, "a leftover strip 3–"));  // its narrowest: 3.0 mm
  EXPECT_TRUE(warnsAbout(r, "left empty"));
  for (const auto& level : r.fitted) {
    ASSERT_EQ(level.size(), 1u);
    EXPECT_TRUE(level[0].closed);
  }
}

TEST(ContourPaths, RectangleWithThinLastRing) {
  // 60 x 36: the last ring (GDTC 16.65 mm) has its long sides 2.7 mm apart; it becomes one
  // centre bead along y = 18 reaching as far as the ring did.
  const ContourCase r =
      checkContourParallel(makeRectangleMesh(0, 60, 0, 36, 120, 72), 3.7, "rectangle 60 x 36");
  EXPECT_NEAR(r.before.self, 2.7, 0.1);  // the case is narrow without the rule
  EXPECT_NEAR(r.strips.closestBefore, 2.7, 0.05);
  expectCentreBeadOnMidline(r, 18.0, 16.65);
  // Under-fill: 1.35 mm along the sides, up to half the detection distance where the ring turns.
  EXPECT_GE(r.strips.widestUnderfill, 1.35);
  EXPECT_LE(r.strips.widestUnderfill, 0.5 * (0.95 * 3.7 + 0.1));
  EXPECT_TRUE(warnsAbout(r, "replaced by one centre bead"));
}

TEST(ContourPaths, RectangleWithTinyLeftoverStrip) {
  // 60 x 33.4: the last ring's sides are only 0.1 mm apart (GDTC ridge 16.7, ring 16.65).
  // (Even row counts put mesh vertices on the ridge, so the mesh resolves it.)
  const ContourCase r =
      checkContourParallel(makeRectangleMesh(0, 60, 0, 33.4, 120, 66), 3.7, "rectangle 60 x 33.4");
  EXPECT_LT(r.before.self, 0.5);
  expectCentreBeadOnMidline(r, 16.7, 16.65);
}

TEST(ContourPaths, RectangleWithLeftoverBead) {
  // 60 x 40.6: no ring at 20.35 (ridge 20.3), the strip beyond the last ring's inner edge is
  // 3.6 mm wide; a centre bead on the ridge is 3.65 mm from the last ring, so it is laid where
  // it keeps 0.95·s + margin (x from 16.65 + 3.62 to 60 − that).
  const ContourCase r =
      checkContourParallel(makeRectangleMesh(0, 60, 0, 40.6, 120, 82), 3.7, "rectangle 60 x 40.6");
  expectCentreBeadOnMidline(r, 20.3, 20.27);
  EXPECT_EQ(r.fitted.back().size(), 2u);  // the last ring and the leftover bead
}

TEST(ContourPaths, LayerWithHole) {
  // A round plate with a concentric hole, 6 bead spacings wide: the paths from the rim and from
  // the hole meet at the middle exactly s apart; nothing is narrow, every ring stays closed.
  const double s = 3.7, ri = 8.0, ro = ri + 6 * s;
  Profile annulus{[](double t) { return t; }, [](double) { return 0.0; }, ri, ro,
                  static_cast<int>(std::lround((ro - ri) / 0.5))};
  const ContourCase r =
      checkContourParallel(makeRevolutionMesh(annulus, 0.5), s, "plate with a hole");
  EXPECT_EQ(r.strips.centreBeads, 0u);
  EXPECT_TRUE(r.strips.warnings.empty());
  for (const auto& level : r.fitted) {
    for (const Polyline& path : level) EXPECT_TRUE(path.closed);
  }
}

TEST(ContourPaths, HoleFrontMeetsRimAllRound) {
  // 5.6 bead spacings wide: the rings at 2.5·s from the hole and from the rim are 0.6·s apart
  // all round; they become one closed centre ring in the middle.
  const double s = 3.7, ri = 8.0, ro = ri + 5.6 * s;
  Profile annulus{[](double t) { return t; }, [](double) { return 0.0; }, ri, ro,
                  static_cast<int>(std::lround((ro - ri) / 0.5))};
  const ContourCase r =
      checkContourParallel(makeRevolutionMesh(annulus, 0.5), s, "plate with a hole, 5.6 s wide");
  EXPECT_NEAR(r.before.sameLevel, 0.6 * s, 0.1);
  ASSERT_EQ(r.strips.centreBeads, 1u);
  const std::vector<Polyline>& last = r.fitted.back();
  ASSERT_EQ(last.size(), 1u);
  EXPECT_TRUE(last[0].closed);
  for (const Vec3& p : last[0].points) EXPECT_NEAR(p.head<2>().norm(), 0.5 * (ri + ro), 0.1);
}

TEST(ContourPaths, EccentricHole) {
  // A plate of radius 30 with a hole of radius 6 centred at (6, 0): 18 mm wide on the +x side,
  // 24 mm on the -x side. The fronts from the hole and the rim merge into horseshoe-shaped
  // iso-lines whose tips are thin loops.
  const double s = 3.7, ri = 6.0, ro = 30.0;
  Profile annulus{[](double t) { return t; }, [](double) { return 0.0; }, ri, ro,
                  static_cast<int>(std::lround((ro - ri) / 0.5))};
  TriMesh mesh = makeRevolutionMesh(annulus, 0.5);
  const Vec3 centre(6.0, 0.0, 0.0);
  for (Vec3& v : mesh.vertices) {
    const double r = v.head<2>().norm();
    const Vec3 u(v.x() / r, v.y() / r, 0.0);
    const double t = (r - ri) / (ro - ri);
    v = (1.0 - t) * (centre + ri * u) + t * (ro * u);
  }
  const ContourCase r = checkContourParallel(mesh, s, "eccentric hole");
  EXPECT_LT(r.before.all(), 0.95 * s);
  EXPECT_GE(r.strips.centreBeads, 1u);
}

TEST(ContourPaths, PlannerReportsTheCentreBead) {
  LayerSurface layer;
  layer.index = 1;
  layer.mesh = makeRectangleMesh(0, 60, 0, 36, 120, 72);
  const PlanResult result = planLayers({layer}, TriMesh{});
  ASSERT_EQ(result.plan.layers.size(), 1u);
  const PlanLayer& planned = result.plan.layers[0];
  // Four closed rings (joined into one path by the connected insets) and one open centre bead.
  const testing::SplitBeads beads = testing::splitLayerBeads(planned.paths);
  ASSERT_EQ(beads.beads.size(), 5u);
  EXPECT_EQ(beads.rings, 4u);
  EXPECT_EQ(planned.paths.size(), 2u);
  bool reported = false;
  for (const std::string& w : planned.warnings) {
    reported = reported || w.find("centre bead") != std::string::npos;
  }
  EXPECT_TRUE(reported);
}

TEST(ContourPaths, CornerAngleDecidesWhichCornersStayExact) {
  // The rings of a rectangle are rectangles: with the default corner angle (30°) the fit keeps
  // their 90° corners as raw vertices and the sides are fitted exactly; with 180° every ring is
  // one smooth spline that rounds its corners within the fit tolerance.
  LayerSurface layer;
  layer.index = 1;
  layer.mesh = makeRectangleMesh(0, 40, 0, 30, 80, 60);
  PlannerOptions options;
  options.beadSpacing = 4.0;
  const PlanResult sharp = planLayers({layer}, TriMesh{}, options);
  EXPECT_EQ(sharp.plan.parameters.cornerAngle, 30.0);
  EXPECT_LT(sharp.stats.maxFitDeviation, 1e-6);
  options.cornerAngle = 180.0;
  const PlanResult round = planLayers({layer}, TriMesh{}, options);
  EXPECT_EQ(round.plan.parameters.cornerAngle, 180.0);
  EXPECT_GT(round.stats.maxFitDeviation, 0.01);
  EXPECT_LE(round.stats.maxFitDeviation, options.fitTolerance + 1e-9);
  ASSERT_EQ(round.plan.layers[0].paths.size(), sharp.plan.layers[0].paths.size());
}

TEST(ContourPaths, AnyRectangleKeepsTheSpacingWithTheDefaultPlanner) {
  // The acceptance rule on rectangles of every width between 12 mm and 41 mm (s = 3.7, so the
  // GDTC ridge falls anywhere between two rings): the planner's output paths (fitted, resampled,
  // ordered) are never closer than 0.95·s — between paths, or within one path beyond π·s/2 along
  // it —, and the outermost ring sits s/2 from the edge. With `overlap` the innermost ring's
  // sides come closer on most widths (the case the default rule exists for). Gap fill is off
  // here: it puts a bead into the strip left between the innermost rings (0.5·s to s wide),
  // deliberately closer than 0.95·s to them (void traded for overlap, paths/gap_fill.hpp); with
  // it on (the default) the void share of every rectangle does not grow and the overlap stays
  // under 10 %.
  const double s = 3.7;
  int overlapping = 0, filled = 0;
  double closestCentre = kInf;
  for (double width = 12.0; width <= 41.0; width += 1.3) {
    LayerSurface layer;
    layer.index = 1;
    const int ny = static_cast<int>(std::lround(width / 0.5));
    layer.mesh = makeRectangleMesh(0, 60, 0, width, 120, ny);
    for (const NarrowStripMode mode : {NarrowStripMode::CentreBead, NarrowStripMode::Overlap}) {
      PlannerOptions options;
      options.narrowStrips = mode;
      options.fillGaps = false;
      const PlanResult result = planLayers({layer}, TriMesh{}, options);
      ASSERT_EQ(result.plan.layers.size(), 1u);
      if (mode == NarrowStripMode::CentreBead) {
        options.fillGaps = true;
        const PlanResult fill = planLayers({layer}, TriMesh{}, options);
        const LayerCoverage& on = fill.plan.layers.at(0).coverage;
        const LayerCoverage& off = result.plan.layers[0].coverage;
        EXPECT_LE(on.voidShare, off.voidShare) << "width " << width;
        EXPECT_LE(on.overlapShare, 0.10) << "width " << width;
        filled += fill.plan.layers[0].paths.size() > result.plan.layers[0].paths.size();
      }
      // Connected insets: the ring parts of a joined path are measured as the rings they are;
      // a link keeps s/2 from every bead but the two it joins.
      const testing::SplitBeads split = testing::splitLayerBeads(result.plan.layers[0].paths);
      const std::vector<Polyline>& paths = split.beads;
      for (const testing::LinkPart& link : split.links) {
        for (std::size_t i = 0; i < paths.size(); ++i) {
          if (i == link.before || i == link.after) continue;
          for (const Vec3& q : link.line.points) {
            EXPECT_GE(closestPointOnPolyline(paths[i], q).distance, 0.5 * s) << "width " << width;
          }
        }
      }
      double closest = kInf, outer = kInf;
      for (std::size_t i = 0; i < paths.size(); ++i) {
        closest = std::min(closest, computeSelfClearance(paths[i], 0.5 * std::numbers::pi * s));
        for (std::size_t j = i + 1; j < paths.size(); ++j) {
          closest = std::min(closest, computePolylineDistance(paths[i], paths[j]));
        }
        for (const Vec3& q : paths[i].points) {
          outer = std::min({outer, q.x(), 60.0 - q.x(), q.y(), width - q.y()});
        }
      }
      if (mode == NarrowStripMode::CentreBead) {
        closestCentre = std::min(closestCentre, closest);
        EXPECT_GE(closest, 0.95 * s) << "width " << width;
        EXPECT_NEAR(outer, 0.5 * s, 0.05) << "width " << width;
      } else if (closest < 0.95 * s) {
        ++overlapping;
      }
    }
  }
  std::cout << "rectangles 60 x 12..41 mm: overlap mode closer than 0.95·s on " << overlapping
            << " of 23 widths; centre-bead mode closest " << closestCentre << " mm; gap fill on "
            << filled << " widths\n";
  EXPECT_GE(overlapping, 8);  // the sweep does cover the case the rule is for
  EXPECT_GT(filled, 0);       // and the strips gap fill is for
}

TEST(Planner, KindNamesRoundTrip) {
  for (InitialCurveKind k :
       {InitialCurveKind::Boundary, InitialCurveKind::Plane, InitialCurveKind::Surface}) {
    EXPECT_EQ(parseInitialCurveKind(toString(k)), k);
  }
  for (WallEdgeKind k : {WallEdgeKind::LowestAlongAxis, WallEdgeKind::NearestToPoint}) {
    EXPECT_EQ(parseWallEdgeKind(toString(k)), k);
  }
  EXPECT_EQ(toString(InitialCurve{}.kind), "boundary");
  EXPECT_EQ(toString(ThinWallOptions{}.edge), "lowest");
  EXPECT_THROW(parseInitialCurveKind("Boundary"), InvalidInput);
  try {
    parseWallEdgeKind("top");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("unknown thin-wall edge: 'top'; choose lowest"),
              std::string::npos)
        << e.what();
  }
}

TEST(NarrowStrips, BadInput) {
  EXPECT_THROW(resolveNarrowStrips({}, {}, 0.0), InvalidInput);
  EXPECT_THROW(resolveNarrowStrips({{}}, {}, 3.7), InvalidInput);
  EXPECT_THROW(resolveNarrowStrips({{}}, {1.85}, 3.7, {}, {{}, {}}), InvalidInput);
  NarrowStripOptions o;
  o.minSeparation = -1.0;
  EXPECT_THROW(resolveNarrowStrips({}, {}, 3.7, o), InvalidInput);
}

TEST(NarrowStrips, TwoParallelLinesBecomeOne) {
  // Two open lines 2 mm apart at one level (s = 3.7): one centre line at y = 1, nothing else.
  Polyline a, b;
  for (int i = 0; i <= 40; ++i) {
    a.points.emplace_back(i, 0.0, 0.0);
    b.points.emplace_back(40 - i, 2.0, 0.0);
  }
  const NarrowStripResult r = resolveNarrowStrips({{a, b}}, {1.85}, 3.7);
  ASSERT_EQ(r.levels.size(), 1u);
  ASSERT_EQ(r.levels[0].size(), 1u);
  EXPECT_TRUE(r.centreBead[0][0]);
  EXPECT_NEAR(r.closestBefore, 2.0, 1e-6);
  EXPECT_NEAR(r.levels[0][0].length(), 40.0, 0.5);
  for (const Vec3& p : r.levels[0][0].points) EXPECT_NEAR(p.y(), 1.0, 1e-9);
  // Far apart: untouched, deterministic.
  Polyline c = b;
  for (Vec3& p : c.points) p.y() = 10.0;
  const NarrowStripResult keep = resolveNarrowStrips({{a, c}}, {1.85}, 3.7);
  ASSERT_EQ(keep.levels[0].size(), 2u);
  EXPECT_EQ(keep.levels[0][0].points, a.points);
  EXPECT_EQ(keep.levels[0][1].points, c.points);
  EXPECT_TRUE(keep.warnings.empty());
}

TEST(NarrowStrips, CentreBeadJoinsTheRingPieceItContinues) {
  // One level's ring around a keyhole: a circle of radius 10 and a tail 2.3 mm wide out to
  // x = 40 (the innermost ring of a part whose tail is 6 mm wide, s = 3.7). The tail's sides are
  // closer than 0.95·s: they become one centre bead along y = 0, and that bead is joined to the
  // open ring piece round the circle, so the level is ONE open path (one arc start), with no two
  // of its points closer than 0.95·s unless they are near each other along it.
  const double s = 3.7, r = 10.0, half = 1.15;
  const double a0 = std::asin(half / r);
  Polyline ring;
  ring.closed = true;
  const double x0 = r * std::cos(a0);
  for (double x = 40.0; x > x0; x -= 0.5) ring.points.emplace_back(x, half, 0.0);
  const int arcs = 200;
  for (int i = 0; i <= arcs; ++i) {
    const double a = a0 + (2.0 * std::numbers::pi - 2.0 * a0) * i / arcs;
    ring.points.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  for (double x = x0 + 0.5; x <= 40.0; x += 0.5) ring.points.emplace_back(x, -half, 0.0);
  const NarrowStripResult joined = resolveNarrowStrips({{ring}}, {1.85}, s);
  EXPECT_EQ(joined.centreBeads, 1u);
  EXPECT_EQ(joined.links, 1u);
  ASSERT_EQ(joined.levels[0].size(), 1u);
  const Polyline& path = joined.levels[0][0];
  EXPECT_FALSE(path.closed);
  EXPECT_TRUE(joined.centreBead[0][0]);
  EXPECT_GE(computeSelfClearance(path, 0.5 * std::numbers::pi * s), 0.95 * s);
  // It still goes round the circle and reaches to the tail's end along its centre line.
  double farthest = 0.0;
  for (const Vec3& p : path.points) {
    if (p.x() > 20.0) {
      EXPECT_NEAR(p.y(), 0.0, 0.01);  // midpoints of s/16 samples
    }
    farthest = std::max(farthest, p.x());
  }
  EXPECT_GT(farthest, 39.0);
  EXPECT_GT(path.length(), 2.0 * std::numbers::pi * r - 2.0 * s + 40.0 - r - 2.0 * s);

  // Linking off: the bead and the ring piece stay two paths.
  NarrowStripOptions apart;
  apart.linkDistance = 0.0;
  const NarrowStripResult two = resolveNarrowStrips({{ring}}, {1.85}, s, apart);
  EXPECT_EQ(two.links, 0u);
  EXPECT_EQ(two.levels[0].size(), 2u);
}

}  // namespace
}  // namespace curvedslicer
