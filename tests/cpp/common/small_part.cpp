#include "common/small_part.hpp"

#include "common/shapes.hpp"

namespace curvedslicer::testing {

TriMesh makeSmallPart() {
  return makeCone(Vec3::Zero(), 15.0, 27.0, 24.0, 48);
}

PlanJobResult planSmallPart() {
  const SmallPartSettings s;
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = s.layerThickness;
  options.layerJob.voxelize.voxelSize = s.voxel;
  options.planner.beadSpacing = s.beadSpacing;
  options.planner.pointSpacing = s.pointSpacing;
  options.modelName = "small_part.stl";
  options.startSpec = "plane:bottom";
  return runPlanJob(makeSmallPart(), options);
}

std::string writeSmallPartStl() {
  return writeTempStl(makeSmallPart(), "small_part.stl");
}

}  // namespace curvedslicer::testing
