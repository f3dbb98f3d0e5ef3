// The two acceptance models of the exporter tests, planned end to end (runPlanJob) at settings
// coarser than the issues' measurements to keep the run time at seconds: the curved example
// (voxel 2 mm, 5 mm point spacing) and the cylinder (3 mm layers, 4 mm voxels, 10 mm bead and
// point spacing). The format and configuration rules the tests check do not depend on the
// resolution.
#pragma once

#include <string>

#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"

namespace curvedslicer::testing {

struct ModelCase {
  std::string model;
  std::string start;  ///< empty: plane:bottom
  bool capHoles = false;
  double layerThickness = 1.5, voxel = 2.0, beadSpacing = 3.7, pointSpacing = 2.0;
};

/// custom_base_geom_to_slice.obj from its curved start surface, holes capped.
inline ModelCase curvedExampleCase() {
  ModelCase c;
  c.model = "custom_base_geom_to_slice.obj";
  c.start = "mesh:" + modelPath("custom_base_surface.obj").string();
  c.capHoles = true;
  c.pointSpacing = 5.0;
  return c;
}

/// simple_cylinder_closed_mid_res.stl from its base.
inline ModelCase cylinderCase() {
  ModelCase c;
  c.model = "simple_cylinder_closed_mid_res.stl";
  c.layerThickness = 3.0;
  c.voxel = 4.0;
  c.beadSpacing = 10.0;
  c.pointSpacing = 10.0;
  return c;
}

inline PlanJobResult planModelCase(const ModelCase& c) {
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = c.layerThickness;
  options.layerJob.voxelize.voxelSize = c.voxel;
  options.layerJob.capHoles = c.capHoles;
  if (!c.start.empty()) options.layerJob.start = loadStartSurface(parseStartSurfaceSpec(c.start));
  options.planner.beadSpacing = c.beadSpacing;
  options.planner.pointSpacing = c.pointSpacing;
  options.modelName = c.model;
  options.startSpec = c.start.empty() ? "plane:bottom" : c.start;
  return runPlanJob(readMesh(modelPath(c.model)), options);
}

}  // namespace curvedslicer::testing
