// Layers through the real pipeline: mesh -> voxelize -> resolveStartSurface ->
// computeGeodesicField -> extractLayers, on solids with closed-form layers, and the paper's
// tessellation-independence claim (figs. 10–11). Voxel size: the longest side has 128 cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/shapes.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/field/start_surface.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer {
namespace {

struct PipelineRun {
  double voxelSize = 0.0;
  LayersResult layers;
};

/// Voxel size giving `cells` cells along the longest side of the mesh's bounding box.
double voxelSizeFor(const TriMesh& mesh, int cells) {
  return mesh.bounds().size().maxCoeff() / cells;
}

PipelineRun runPipeline(const TriMesh& model, const StartSurface& start, double h,
                        double voxelSize) {
  PipelineRun run;
  run.voxelSize = voxelSize;
  VoxelizeOptions voxelOptions;
  voxelOptions.voxelSize = voxelSize;
  const VoxelizeResult voxels = voxelize(model, voxelOptions);
  const TriMesh source = resolveStartSurface(model, start);
  const GeodesicResult field = computeGeodesicField(voxels.grid, model, source);
  EXPECT_EQ(field.unreached.count, 0u);
  LayerOptions options;
  options.layerThickness = h;
  run.layers = extractLayers(field.field, voxels.grid, model, source, options);
  return run;
}

using std::numbers::pi;

/// Vertices on edges that only one triangle uses.
std::vector<int> rimVertices(const TriMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  for (const Vec3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back(std::minmax(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::vector<int> rim;
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t next = e + 1;
    while (next < edges.size() && edges[next] == edges[e]) ++next;
    if (next - e == 1) {
      rim.push_back(edges[e].first);
      rim.push_back(edges[e].second);
    }
    e = next;
  }
  return rim;
}

/// Symmetric Hausdorff distance between two meshes, measured at their vertices.
double vertexHausdorff(const TriMesh& a, const TriMesh& b) {
  const TriangleBvh bvhA(a), bvhB(b);
  double worst = 0.0;
  for (const Vec3& v : a.vertices) worst = std::max(worst, bvhB.distance(v));
  for (const Vec3& v : b.vertices) worst = std::max(worst, bvhA.distance(v));
  return worst;
}

TEST(LayersPipeline, CylinderFromItsBaseGivesPlanes) {
  const double radius = 4.0, height = 16.0, h = 1.5;
  const TriMesh model = testing::makeCylinder(Vec3(0.3, -0.2, 1.0), radius, height, 48);
  const PipelineRun run =
      runPipeline(model, StartSurface::buildPlate(), h, voxelSizeFor(model, 128));
  const double L = run.voxelSize;
  ASSERT_EQ(run.layers.surfaces.size(), 10u);  // 10·1.5 = 15 <= 16 − L/2 < 11·1.5
  const TriangleBvh surface(model);
  for (const LayerSurface& layer : run.layers.surfaces) {
    SCOPED_TRACE("layer " + std::to_string(layer.index));
    ASSERT_FALSE(layer.mesh.empty());
    double deviation = 0.0;
    for (const Vec3& v : layer.mesh.vertices) {
      deviation = std::max(deviation, std::abs(v.z() - (1.0 + layer.level)));
    }
    EXPECT_LT(deviation, 0.25 * L);
    EXPECT_EQ(layer.components, 1u);
    const double disk = 0.5 * 48 * radius * radius * std::sin(2 * pi / 48);
    EXPECT_NEAR(layer.area, disk, 0.01 * disk);
    EXPECT_NEAR(layer.thicknessToPrevious.mean, h, 0.25 * L);
    const std::vector<int> rim = rimVertices(layer.mesh);
    ASSERT_FALSE(rim.empty());
    double offSurface = 0.0;
    for (int v : rim) offSurface = std::max(offSurface, surface.distance(layer.mesh.vertices[v]));
    EXPECT_LT(offSurface, 1e-6);
  }
}

TEST(LayersPipeline, ShellFromItsInnerSphereGivesSpheres) {
  const Vec3 centre(0.2, -0.1, 0.3);
  const double r1 = 4.0, r2 = 10.0, h = 1.5;
  const TriMesh model = testing::makeSphericalShell(centre, r1, r2, 4);
  const StartSurface inner = StartSurface::surface(testing::makeSphere(centre, r1, 4));
  const PipelineRun run = runPipeline(model, inner, h, voxelSizeFor(model, 128));
  const double L = run.voxelSize;
  ASSERT_EQ(run.layers.surfaces.size(), 3u);  // radii 5.5, 7, 8.5
  for (const LayerSurface& layer : run.layers.surfaces) {
    SCOPED_TRACE("layer " + std::to_string(layer.index));
    const double radius = r1 + layer.level;
    double deviation = 0.0;
    for (const Vec3& v : layer.mesh.vertices) {
      deviation = std::max(deviation, std::abs((v - centre).norm() - radius));
    }
    EXPECT_LT(deviation, 0.25 * L);
    EXPECT_EQ(layer.components, 1u);
    EXPECT_NEAR(layer.area, 4 * pi * radius * radius, 0.01 * 4 * pi * radius * radius);
    EXPECT_TRUE(rimVertices(layer.mesh).empty());  // closed
    EXPECT_NEAR(layer.thicknessToPrevious.mean, h, 0.25 * L);
  }
}

TEST(LayersPipeline, LayersDoNotDependOnTessellation) {
  // Paper figs. 10–11: facet offsetting depends on triangle size and angle, voxel geodesic
  // layers must not. The same 12-gon prism, three tessellations.
  const Vec3 base(0.0, 0.0, 0.0);
  const double radius = 4.0, height = 16.0, h = 2.0;
  const TriMesh coarse = testing::makeCylinder(base, radius, height, 12);
  const TriMesh fine = testing::makeFineCylinder(base, radius, height, 12, 5000);
  const TriMesh sliver = testing::makeSliverCylinder(base, radius, height, 12);
  ASSERT_LT(coarse.triangleCount(), 60u);
  ASSERT_GT(fine.triangleCount(), 4000u);
  const double L = voxelSizeFor(coarse, 128);
  const PipelineRun a = runPipeline(coarse, StartSurface::buildPlate(), h, L);
  const PipelineRun b = runPipeline(fine, StartSurface::buildPlate(), h, L);
  const PipelineRun c = runPipeline(sliver, StartSurface::buildPlate(), h, L);
  ASSERT_EQ(a.layers.surfaces.size(), 7u);
  ASSERT_EQ(b.layers.surfaces.size(), a.layers.surfaces.size());
  ASSERT_EQ(c.layers.surfaces.size(), a.layers.surfaces.size());
  for (std::size_t i = 0; i < a.layers.surfaces.size(); ++i) {
    SCOPED_TRACE("layer " + std::to_string(i + 1));
    const TriMesh& ref = a.layers.surfaces[i].mesh;
    EXPECT_LT(vertexHausdorff(ref, b.layers.surfaces[i].mesh), 0.5 * L);
    EXPECT_LT(vertexHausdorff(ref, c.layers.surfaces[i].mesh), 0.5 * L);
  }
}

}  // namespace
}  // namespace curvedslicer
