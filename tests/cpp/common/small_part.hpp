// The small part of the sanitizer build: what the whole-model tests (the curved example and the
// cylinder, tests/cpp/export/model_plans.hpp and the robot tests) check on a plan that takes
// seconds under AddressSanitizer. An overhanging cone (radius 15 mm at the build plate widening
// to 27 mm at 24 mm height, 48 facets) planned end to end by runPlanJob from the plate: curved
// layers at the overhang (V tilted, so the positioner turns), several rings per layer joined by
// connected insets into open welds, gap fill, layer dwells. Same code as the whole models:
// runPlanJob, planMotion, the exporters and their readers; only the size differs.
#pragma once

#include <string>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"

namespace curvedslicer::testing {

/// The part's settings, as `curvedslicer plan` options (mm).
struct SmallPartSettings {
  double layerThickness = 3.0, voxel = 2.0, beadSpacing = 3.7, pointSpacing = 5.0;
};

/// The overhanging cone, base on z = 0 around the z axis (mm).
TriMesh makeSmallPart();

/// The cone planned end to end (runPlanJob, plane:bottom, the settings above).
PlanJobResult planSmallPart();

/// The cone written as a binary STL into a fresh temporary folder (writeTempStl); its path.
std::string writeSmallPartStl();

}  // namespace curvedslicer::testing
