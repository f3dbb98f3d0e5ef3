// In-process tests of pipeline/layer_pipeline.hpp: the stages run in order with their progress
// ranges, and every validation fails with the specific InvalidInput before heavy work.
#include "curvedslicer/pipeline/layer_pipeline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/shapes.hpp"
#include "common/text_assertions.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using testing::makeBox;
using Names = std::vector<std::string>;

using testing::contains;

template <typename E, typename F>
std::string messageOf(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected an exception";
  return {};
}

LayerJobOptions boxOptions() {
  LayerJobOptions o;
  o.voxelize.voxelSize = 0.5;
  o.layers.layerThickness = 2.0;
  return o;
}

TEST(LayerPipeline, RejectsBadParametersBeforeAnyWork) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double h : {0.0, -1.5, nan, inf}) {
    LayerJobOptions o = boxOptions();
    o.layers.layerThickness = h;
    int calls = 0;
    const std::string message = messageOf<InvalidInput>([&] {
      runLayerJob(box, o, Progress([&](double, std::string_view) { return ++calls > 0; }));
    });
    EXPECT_TRUE(contains(message, "layer thickness must be a positive number")) << h;
    EXPECT_EQ(calls, 0) << "validation must come before the first stage";
  }
  for (double L : {0.0, -0.5, nan, inf}) {
    LayerJobOptions o = boxOptions();
    o.voxelize.voxelSize = L;
    EXPECT_TRUE(contains(messageOf<InvalidInput>([&] { runLayerJob(box, o); }),
                         "voxel size must be a positive number"))
        << L;
  }
  LayerJobOptions o = boxOptions();
  o.voxelize.memoryBudgetBytes = -1.0;
  EXPECT_TRUE(contains(messageOf<InvalidInput>([&] { runLayerJob(box, o); }), "memory budget"));
  EXPECT_TRUE(contains(messageOf<InvalidInput>([&] { runLayerJob(TriMesh{}, boxOptions()); }),
                       "no triangles"));
}

TEST(LayerPipeline, RunsEveryStageOnABox) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  std::vector<double> fractions;
  Names stages;
  const LayerJobResult r =
      runLayerJob(box, boxOptions(), Progress([&](double f, std::string_view stage) {
                    fractions.push_back(f);
                    if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
                    return true;
                  }));
  Names timed;
  for (const StageTime& t : r.stageTimes) {
    timed.push_back(t.name);
    EXPECT_GE(t.seconds, 0.0);
  }
  EXPECT_EQ(timed, (Names{"clean", "start surface", "analyze", "voxelize", "field", "layers"}));
  ASSERT_FALSE(fractions.empty());
  for (std::size_t k = 1; k < fractions.size(); ++k) EXPECT_GE(fractions[k], fractions[k - 1]);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_EQ(stages.front(), "clean");
  EXPECT_EQ(stages.back(), "layers");

  EXPECT_TRUE(r.meshReport.closed());
  EXPECT_NEAR(r.meshReport.volume, 1000.0, 1e-9);
  EXPECT_GT(r.voxelization.grid.insideCount, 7000u);
  EXPECT_EQ(r.voxelization.stats.unresolvedVoxels, 0u);
  EXPECT_EQ(r.field.unreached.count, 0u);
  // Distance from the build plate is the height: the top voxel centres sit at 10 − L/2.
  EXPECT_NEAR(r.field.maxDistance, 9.75, 0.5);
  ASSERT_EQ(r.layers.surfaces.size(), 4u);  // levels 2, 4, 6, 8
  for (std::size_t k = 0; k < r.layers.surfaces.size(); ++k) {
    const LayerSurface& s = r.layers.surfaces[k];
    EXPECT_EQ(s.index, static_cast<int>(k) + 1);
    EXPECT_DOUBLE_EQ(s.level, 2.0 * (k + 1));
    EXPECT_GT(s.mesh.triangleCount(), 0u);
    EXPECT_NEAR(s.area, 100.0, 5.0);  // horizontal 10 x 10 sections
  }
  EXPECT_FALSE(r.startDescription.empty());
  EXPECT_GT(r.totalSeconds, 0.0);
  EXPECT_GT(r.peakMemoryBytes, 0u);
}

TEST(LayerPipeline, IsDeterministic) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(6, 8, 10));
  const LayerJobResult a = runLayerJob(box, boxOptions());
  const LayerJobResult b = runLayerJob(box, boxOptions());
  EXPECT_EQ(a.field.field.distance, b.field.field.distance);
  ASSERT_EQ(a.layers.surfaces.size(), b.layers.surfaces.size());
  for (std::size_t k = 0; k < a.layers.surfaces.size(); ++k) {
    EXPECT_EQ(a.layers.surfaces[k].mesh.vertices, b.layers.surfaces[k].mesh.vertices);
    EXPECT_EQ(a.layers.surfaces[k].mesh.triangles, b.layers.surfaces[k].mesh.triangles);
  }
}

/// Keeps the surfaces and voxel sets a streaming job hands over.
class KeepingSink final : public LayerSink {
 public:
  int layerCount = -1;
  std::vector<LayerSurface> surfaces;
  std::vector<VoxelLayerSet> sets;
  void begin(int count, const std::vector<std::size_t>&, const GridGeometry&) override {
    layerCount = count;
  }
  void acceptSurface(LayerSurface&& surface) override { surfaces.push_back(std::move(surface)); }
  void acceptVoxelSet(VoxelLayerSet&& set, const std::vector<float>&) override {
    sets.push_back(std::move(set));
  }
};

TEST(LayerPipeline, StreamingJobHandsOverTheSameLayersAndReleasesTheVolumes) {
  const TriMesh sphere = testing::makeSphere(Vec3(1, 2, 3), 5.0, 3);
  LayerJobOptions o = boxOptions();
  o.layers.layerThickness = 1.3;
  const LayerJobResult inMemory = runLayerJob(sphere, o);  // automatic batches: one here
  o.layers.batchCrossings = 400;                           // several batches
  KeepingSink sink;
  const LayerJobResult streamed = runLayerJob(sphere, o, sink);

  ASSERT_EQ(sink.layerCount, static_cast<int>(inMemory.layers.surfaces.size()));
  ASSERT_EQ(sink.surfaces.size(), inMemory.layers.surfaces.size());
  ASSERT_EQ(sink.sets.size(), inMemory.layers.voxelSets.size());
  for (std::size_t k = 0; k < sink.surfaces.size(); ++k) {
    EXPECT_EQ(sink.surfaces[k].mesh.vertices, inMemory.layers.surfaces[k].mesh.vertices);
    EXPECT_EQ(sink.surfaces[k].mesh.triangles, inMemory.layers.surfaces[k].mesh.triangles);
    EXPECT_EQ(sink.sets[k].cells, inMemory.layers.voxelSets[k].cells);
    EXPECT_EQ(streamed.layers.summaries[k].triangles, inMemory.layers.summaries[k].triangles);
    EXPECT_EQ(streamed.layers.summaries[k].voxelSetSize, inMemory.layers.summaries[k].voxelSetSize);
  }
  EXPECT_GT(streamed.layers.batches, 1u);
  EXPECT_EQ(inMemory.layers.batches, 1u);
  // The streaming form keeps summaries only and has released the volume arrays.
  EXPECT_TRUE(streamed.layers.surfaces.empty());
  EXPECT_TRUE(streamed.layers.voxelSets.empty());
  EXPECT_TRUE(streamed.field.field.distance.empty());
  EXPECT_TRUE(streamed.voxelization.grid.inside.empty());
  EXPECT_EQ(streamed.field.field.geometry.dims, inMemory.field.field.geometry.dims);
  EXPECT_EQ(streamed.voxelization.grid.insideCount, inMemory.voxelization.grid.insideCount);
  EXPECT_EQ(streamed.field.maxDistance, inMemory.field.maxDistance);
  // The in-memory form keeps everything.
  EXPECT_EQ(inMemory.field.field.distance.size(), inMemory.field.field.geometry.cellCount());
  EXPECT_EQ(inMemory.voxelization.grid.inside.size(), inMemory.field.field.geometry.cellCount());
}

TEST(LayerPipeline, CancelsFromTheProgressCallback) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  for (const char* stopAt : {"voxelize", "field", "layers"}) {
    bool seen = false;
    EXPECT_THROW(runLayerJob(box, boxOptions(), Progress([&](double, std::string_view stage) {
                               seen = seen || stage == stopAt;
                               return !seen;
                             })),
                 Cancelled)
        << stopAt;
  }
}

TEST(LayerPipeline, RejectsAFlatModel) {
  const TriMesh flat = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 0));
  EXPECT_TRUE(contains(messageOf<InvalidInput>([&] { runLayerJob(flat, boxOptions()); }),
                       "model encloses no volume"));
}

TEST(LayerPipeline, RejectsAVoxelSizeTooCoarseForTheModel) {
  const TriMesh small = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  LayerJobOptions o = boxOptions();
  o.voxelize.voxelSize = 2.0;
  o.layers.layerThickness = 0.2;
  const std::string message = messageOf<InvalidInput>([&] { runLayerJob(small, o); });
  EXPECT_TRUE(contains(message, "voxel size too coarse for the model: 2 mm gives"));
  EXPECT_TRUE(contains(message, "use a voxel size of about 0.1 mm or smaller"));
}

TEST(LayerPipeline, RejectsALayerThicknessBeyondThePart) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  LayerJobOptions o = boxOptions();
  o.layers.layerThickness = 25.0;
  EXPECT_TRUE(contains(messageOf<InvalidInput>([&] { runLayerJob(box, o); }),
                       "layer thickness exceeds the part's extent from the start surface"));
}

TEST(LayerPipeline, GridBeyondTheBudgetFailsBeforeAllocating) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(100, 100, 100));
  LayerJobOptions o = boxOptions();
  o.voxelize.voxelSize = 0.05;              // 8e9 cells
  o.voxelize.memoryBudgetBytes = 64 << 20;  // 64 MiB
  bool voxelizeStarted = false;
  EXPECT_THROW(runLayerJob(box, o, Progress([&](double, std::string_view stage) {
                             voxelizeStarted = voxelizeStarted || stage == "voxelize";
                             return true;
                           })),
               ResourceLimit);
  EXPECT_FALSE(voxelizeStarted);
}

}  // namespace
}  // namespace curvedslicer
