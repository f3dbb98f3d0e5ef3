// The layer job: from a raw triangle soup to curved layers, the whole of paper §2 in one call.
//
// Stages (the progress stage names, with their share of the overall progress):
//   clean (0–0.005)        cleanMesh: weld, drop degenerate/duplicate triangles
//   start surface          resolveStartSurface: the start surface as source triangles (part frame)
//   cap holes              only with `capHoles`: capHoles (hole_capping.hpp), no-op when closed
//   analyze (0.01–0.02)    analyzeMesh + validation of the model (encloses a volume? grid within
//                          the memory budget?)
//   voxelize (0.02–0.2)    voxelize (paper §2.1) + validation of the grid (enough inside voxels?
//                          open mesh beyond repair?)
//   field (0.2–0.8)        computeGeodesicField (paper §2.2)
//   layers (0.8–1)         extractLayers (paper §2.3, eq. 13)
// with wall time per stage and the process's peak resident memory.
//
// Preconditions: none on the mesh (anything readMesh returns); every problem is reported as an
// exception from core/error.hpp with a message "<what>: <value>; <what to do>". Parameters are
// checked before any heavy work. Cost: dominated by the field (O(V log V) for V inside voxels)
// and the layer extraction (see layers/layer_extraction.hpp); memory about
// VoxelizeOptions::bytesPerCell per grid cell (checked against the budget up front) plus the
// layer surfaces — all of them for the in-memory form, one batch for the streaming form (the one
// with a LayerSink), which also hands the field to the extraction (extended there in place and
// freed) and frees the inside mask once the layers are done.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/field/start_surface.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/pipeline/hole_capping.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer {

struct LayerJobOptions {
  StartSurface start;        ///< default: the build plate under the model (z = model min z)
  CleanOptions clean;        ///< default: weld at 1e-6 of the diagonal, drop degenerate/duplicates
  VoxelizeOptions voxelize;  ///< voxelSize = L (mm), alignment, memory budget (bytes)
  GeodesicOptions geodesic;  ///< method (default any-angle), seed band
  LayerOptions layers;       ///< layerThickness = h (mm)
  /// Close the boundary loops of an open model before voxelizing (hole_capping.hpp; caps on the
  /// start surface follow it, ring spacing = voxel size, on-surface tolerance = L/4). Off by
  /// default: an open model is then an error unless the voxelizer can resolve it.
  bool capHoles = false;
  /// Fewer inside voxels than this means the voxel size is too coarse for the model.
  std::size_t minInsideVoxels = 8;
  /// The mesh counts as open beyond repair when more than this fraction of the inside voxels
  /// (or any voxel, if there are no inside voxels) could not be classified by the voxelizer.
  double maxUnresolvedFraction = 0.01;
};

/// Wall time of one stage.
struct StageTime {
  std::string name;  ///< the progress stage name ("clean", "voxelize", …)
  double seconds = 0.0;
  /// Peak resident set size of the process when the stage ended, bytes (the maximum so far, so
  /// a stage that raised it shows by a larger value than the stage before).
  std::size_t peakMemoryBytes = 0;
};

struct LayerJobResult {
  CleanResult clean;             ///< the model as sliced (cleaned, holes capped) and repair counts
  HoleCappingResult capping;     ///< hole statistics (its `mesh` is left empty; see clean.mesh)
  MeshReport meshReport;         ///< of the model as sliced
  std::string startDescription;  ///< StartSurface::describe()
  TriMesh source;                ///< start-surface triangles, part frame
  VoxelizeResult voxelization;   ///< grid (inside mask) and voxelizer statistics
  GeodesicResult field;          ///< distance field and its diagnostics
  /// Surfaces, eq. 13 voxel sets and per-layer summaries, by increasing index. The streaming
  /// form keeps only the summaries (the sink received the rest), and leaves `field.field` with
  /// its geometry but no distances and `voxelization.grid` without its inside mask.
  LayersResult layers;
  std::vector<StageTime> stageTimes;  ///< in execution order
  double totalSeconds = 0.0;
  /// Geometry the voxelizer had to interpret, each saying where (part frame): an open model, a
  /// surface filled by crossing parity, overlapping shells. Empty for a closed, consistently
  /// oriented single-shell model. In report.json "warnings"; the command line prints them.
  std::vector<std::string> warnings;
  /// Peak resident set size of the whole process so far (getrusage ru_maxrss), bytes. In a
  /// process that runs several jobs it is the maximum over all of them.
  std::size_t peakMemoryBytes = 0;
};

/// Checks the parameters of a job without touching any geometry (cheap): layer thickness and
/// voxel size positive and finite, memory budget not negative, geodesic and layer limits sane.
/// @throws InvalidInput naming the parameter and its value.
void validateLayerJobOptions(const LayerJobOptions& options);

/// Runs the stages listed in the file comment on `rawModel` (part frame, mm; a soup or an indexed
/// mesh, with face ids for start surfaces of kind Faces).
/// @throws InvalidInput — bad parameters (see validateLayerJobOptions), an empty model, a model
///         that encloses no volume, a voxel size so coarse that fewer than `minInsideVoxels`
///         inside voxels remain, an open mesh the voxelizer could not resolve, a start surface that
///         does not touch the solid, a layer thickness larger than the part, and any InvalidInput
///         of the stages;
///         ResourceLimit — grid beyond the memory budget (before allocating it);
///         NumericalFailure — from the stages; Cancelled — when `progress` asks to stop.
///         No partial result is ever returned.
LayerJobResult runLayerJob(const TriMesh& rawModel, const LayerJobOptions& options = {},
                           Progress progress = {});

/// The same for big jobs: every layer surface and voxel set goes to `sink` as soon as it is
/// finished (see streamLayers in layers/layer_extraction.hpp) and is not kept; `result.layers`
/// holds the per-layer summaries. The field and the inside mask are released on the way (see
/// LayerJobResult::layers). Same errors; after an exception the sink may have received some
/// layers and must discard them.
LayerJobResult runLayerJob(const TriMesh& rawModel, const LayerJobOptions& options, LayerSink& sink,
                           Progress progress = {});

/// Peak resident set size of this process so far, bytes (0 where the OS does not tell).
std::size_t peakResidentMemoryBytes();

}  // namespace curvedslicer
