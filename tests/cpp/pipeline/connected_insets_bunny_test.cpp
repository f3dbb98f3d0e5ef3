// Issue 15 acceptance for connected insets, on the bundled bunny at the settings
// (h 1.5, L 1, s 3.7): joining consecutive rings cuts the arc starts (number of paths) by at least
// 30 % with no loss of coverage (void share, measured here independently of the planner: the share
// of layer area farther than s/2 from every path's centre line, on a barycentric sample grid of
// every layer triangle), and every link stays inside the layer region: its points lie on the layer
// surface (within the fit tolerance) and keep s/2 from every bead of the layer but the two it
// joins. Layers are computed once and planned with the option off and on. The same plan carries
// the bunny's void acceptance: its total void share by the plan's own coverage numbers
// (paths/coverage.hpp, area-weighted over the layers; gap fill on, the default) is at most 1.5 %.
// Too slow under sanitizers (981 s of the 1200 s timeout under ASan): skipped there; gap fill is
// covered by tests/cpp/paths/gap_fill_test.cpp, connected insets by connected_insets_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_map>
#include <vector>

#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "paths/joined_paths.hpp"

namespace curvedslicer {
namespace {

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// The segments of a layer's paths (closing segments of closed paths included) in a hash grid
/// of cells `reach` wide, each segment in every cell its box grown by `reach` meets.
class SegmentHash {
 public:
  SegmentHash(const std::vector<PlanPath>& paths, double reach) : reach_(reach) {
    for (const PlanPath& path : paths) {
      const std::size_t n = path.points.size();
      const std::size_t count = path.closed ? n : n - 1;
      for (std::size_t i = 0; i < count; ++i) {
        add(path.points[i].position, path.points[(i + 1) % n].position);
      }
    }
  }
  /// True if a segment's centre line is within `reach` of p.
  bool covers(const Vec3& p) const {
    const auto it = cells_.find(key(cellOf(p)));
    if (it == cells_.end()) return false;
    for (const std::size_t s : it->second) {
      if (distanceToSegment(p, segments_[s].first, segments_[s].second) <= reach_) return true;
    }
    return false;
  }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / reach_)),
                           static_cast<int>(std::floor(p.y() / reach_)),
                           static_cast<int>(std::floor(p.z() / reach_)));
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x() + 100000) * 200003 + (c.y() + 100000)) * 200003 +
           (c.z() + 100000);
  }
  void add(const Vec3& a, const Vec3& b) {
    segments_.emplace_back(a, b);
    const Vec3 grow = Vec3::Constant(reach_);
    const Eigen::Vector3i lo = cellOf(a.cwiseMin(b) - grow), hi = cellOf(a.cwiseMax(b) + grow);
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) {
          cells_[key({x, y, z})].push_back(segments_.size() - 1);
        }
      }
    }
  }
  double reach_;
  std::vector<std::pair<Vec3, Vec3>> segments_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

struct Coverage {
  double area = 0.0, voidArea = 0.0;
  double voidShare() const { return area > 0.0 ? voidArea / area : 0.0; }
};

/// Void area of one layer: each triangle cut into m² sub-triangles (m = longest edge / 0.5 mm),
/// each counted at its centroid.
void addLayerCoverage(const TriMesh& mesh, const std::vector<PlanPath>& paths, double s,
                      Coverage& c) {
  const SegmentHash hash(paths, 0.5 * s);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    const Vec3& b = mesh.vertices[mesh.triangles[t][1]];
    const Vec3& d = mesh.vertices[mesh.triangles[t][2]];
    const double longest = std::max({(b - a).norm(), (d - b).norm(), (a - d).norm()});
    const int m = std::max(1, static_cast<int>(std::ceil(longest / 0.5)));
    const double sub = 0.5 * (b - a).cross(d - a).norm() / (m * m);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        // The upright sub-triangle (i, j) and, where it exists, the inverted one beside it.
        const Vec3 p = a + ((i + 1.0 / 3) * (b - a) + (j + 1.0 / 3) * (d - a)) / m;
        c.area += sub;
        if (!hash.covers(p)) c.voidArea += sub;
        if (i + j + 1 < m) {
          const Vec3 q = a + ((i + 2.0 / 3) * (b - a) + (j + 2.0 / 3) * (d - a)) / m;
          c.area += sub;
          if (!hash.covers(q)) c.voidArea += sub;
        }
      }
    }
  }
}

/// The bunny's layers at the settings (h 1.5, L 1), computed once for the suite.
class ConnectedInsetsBunny : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (testing::sanitizedBuild()) return;
    const TriMesh model = readMesh(testing::modelPath("bunny_closed_low_res.stl"));
    LayerJobOptions job;
    job.layers.layerThickness = 1.5;
    job.voxelize.voxelSize = 1.0;
    layers_ = new LayerJobResult(runLayerJob(model, job));
  }
  static void TearDownTestSuite() {
    delete layers_;
    layers_ = nullptr;
  }
  static const LayerJobResult* layers_;
};
const LayerJobResult* ConnectedInsetsBunny::layers_ = nullptr;

TEST_F(ConnectedInsetsBunny, FewerArcStartsSameCoverageLinksInside) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "ConnectedInsets.PlannerJoinsTheSameBeadsAndStaggersSeams and GapFill.*");
  const LayerJobResult& layers = *layers_;
  const std::vector<LayerSurface>& surfaces = layers.layers.surfaces;
  PlannerOptions options;
  options.beadSpacing = 3.7;
  const double s = options.beadSpacing;
  options.connectInsets = false;
  const PlanResult separate = planLayers(surfaces, layers.source, options);
  options.connectInsets = true;
  const PlanResult joined = planLayers(surfaces, layers.source, options);

  const std::size_t before = separate.plan.pathCount(), after = joined.plan.pathCount();
  Coverage coverBefore, coverAfter;
  std::size_t links = 0, linkPoints = 0;
  double farthestFromSurface = 0.0, nearestOtherBead = kInf;
  for (std::size_t l = 0; l < surfaces.size(); ++l) {
    const std::vector<PlanPath>& paths = joined.plan.layers[l].paths;
    addLayerCoverage(surfaces[l].mesh, separate.plan.layers[l].paths, s, coverBefore);
    addLayerCoverage(surfaces[l].mesh, paths, s, coverAfter);
    const testing::SplitBeads split = testing::splitLayerBeads(paths);
    if (split.links.empty()) continue;
    const TriangleBvh surface(surfaces[l].mesh);
    for (const testing::LinkPart& link : split.links) {
      ++links;
      for (const Vec3& q : link.line.points) {
        ++linkPoints;
        farthestFromSurface = std::max(farthestFromSurface, surface.closestPoint(q).distance);
        for (std::size_t i = 0; i < split.beads.size(); ++i) {
          if (i == link.before || i == link.after) continue;
          nearestOtherBead =
              std::min(nearestOtherBead, closestPointOnPolyline(split.beads[i], q).distance);
        }
      }
    }
  }
  std::printf(
      "bunny h 1.5 L 1 s 3.7: %zu layers, arc starts %zu -> %zu (%.1f %% fewer), %zu links "
      "(%zu points), void share %.4f %% -> %.4f %%, link points at most %.2e mm off the surface, "
      "at least %.3f mm from other beads\n",
      surfaces.size(), before, after, 100.0 * (1.0 - double(after) / double(before)), links,
      linkPoints, 100.0 * coverBefore.voidShare(), 100.0 * coverAfter.voidShare(),
      farthestFromSurface, nearestOtherBead);
  ASSERT_GT(before, 0u);
  EXPECT_LE(double(after), 0.7 * double(before));
  EXPECT_EQ(joined.stats.insetLinks, links);
  EXPECT_EQ(before - after, links);
  EXPECT_LE(coverAfter.voidShare(), coverBefore.voidShare());
  EXPECT_LE(farthestFromSurface, options.fitTolerance);
  EXPECT_GE(nearestOtherBead, 0.5 * s);
  const PlanCoverageSummary own = summarizeCoverage(joined.plan);
  std::printf("bunny plan's own coverage: void %.4f %%, overlap %.4f %%, arc starts %zu\n",
              100.0 * own.voidShare, 100.0 * own.overlapShare, own.arcStarts);
  EXPECT_EQ(own.measuredLayers, surfaces.size());
  EXPECT_LE(own.voidShare, 0.015);
}

// The bunny's void acceptance with adaptive bead width on (issue 15: 0.7·s to 1.3·s), by the
// plan's own coverage numbers, which measure each bead with its own per-point width.
TEST_F(ConnectedInsetsBunny, AdaptiveWidthAtMostOneAndAHalfPercentVoid) {
  CURVEDSLICER_SKIP_IF_SANITIZED("AdaptiveWidth.* and GapFill.*");
  PlannerOptions options;
  options.beadSpacing = 3.7;
  options.widthMin = 0.7;
  options.widthMax = 1.3;
  const PlanResult plan = planLayers(layers_->layers.surfaces, layers_->source, options);
  const PlanCoverageSummary own = summarizeCoverage(plan.plan);
  std::printf("bunny adaptive 0.7-1.3: void %.4f %%, overlap %.4f %%, arc starts %zu\n",
              100.0 * own.voidShare, 100.0 * own.overlapShare, own.arcStarts);
  EXPECT_EQ(own.measuredLayers, layers_->layers.surfaces.size());
  EXPECT_LE(own.voidShare, 0.015);
}

}  // namespace
}  // namespace curvedslicer
