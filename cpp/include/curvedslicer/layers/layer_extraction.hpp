// Curved layers from the geodesic field (paper §2.3).
//
// Layer i (i = 1, 2, … while i·h ≤ the largest reached distance) is the iso-surface d = i·h of the
// field. Two representations:
//  - the paper's voxel sets S_i = {P : i·h − L/2 ≤ t_P ≤ i·h + L/2} (eq. 13); a voxel belongs to
//    two sets when h < L;
//  - a triangle surface, built in four steps:
//    1. Extension: the field exists only on reached inside cells. Outside cells within 2 cells
//       (Chebyshev) of a reached cell get a weighted least-squares linear fit d ≈ a + g·(x − x0)
//       over the reached cells of the surrounding 7³ box (weights 1/|x − x0|²); gradient
//       directions the samples do not span (one-cell-thick walls, rods) get no gradient component,
//       and with no direction spanned the nearest reached value is used. A linear field is
//       extended exactly, so iso-surfaces cross the model boundary straight.
//    2. Marching tetrahedra on the dual grid (cubes whose corners are 8 cell centres), each cube
//       split into the 6 Kuhn tetrahedra around its main diagonal — consistent across cubes, so
//       the surface is watertight away from its rim without ambiguous cases. Vertices are linear
//       on tetrahedron edges and shared through a key of the global grid edge. One pass over the
//       cubes serves all levels (parallel over fixed x slabs, merged in slab order, so the output
//       does not depend on the thread count). Cubes with a corner lacking a value are skipped.
//    3. Clipping (optional): every vertex gets its side of the model surface — from the voxel
//       mask where no model triangle meets its cell, else from the exact signed distance
//       (geom/triangle_bvh.hpp, pseudo-normal sign). Triangles crossing the surface are split at
//       the linear zero of the signed distance; the new rim vertices (and vertices within 1e-6·L
//       of the surface) are moved to their closest point on the model surface, so the rim lies
//       on it. Triangles with repeated vertices or zero area and unused vertices are removed.
//    3b. Simplification (opt-in, `LayerOptions::simplification`): edge collapse within a
//       distance ε of the full-resolution surface (default 0.05·L), edges at most 3·L, the rim
//       held fixed (layers/layer_simplification.hpp).
//    4. Statistics: area, connected components (triangles sharing an edge), and the thickness to
//       the previous layer: distances from this layer's vertices (or a sample of them, see
//       `LayerOptions::thicknessSamples`) to the previous layer's surface — for layer 1 to the
//       start surface.
// Layers are built in batches of consecutive levels (one marching pass over the slabs that meet
// them per batch, sized from a first scan that counts the cubes each level crosses) and handed
// over layer by layer: `extractLayers` collects them all in memory; `streamLayers` gives each to
// a `LayerSink` as soon as it is finished and keeps only its statistics, so that big jobs hold one
// batch of layers at a time. A layer's surface does not depend on the batching.
// Preconditions: `field` computed on `grid` (same geometry); `model` the closed, outward-oriented
// surface the grid was voxelized from (only when clipping).
// Cost: O(cells) for the extension scan, the crossing count and each batch's marching and eq. 13
// passes, closest-point queries for vertices in cells the model surface passes through and for
// the thickness samples, and one hierarchy per layer for the thickness. Memory besides the inputs:
// the extended field (4 bytes per cell; in place of the field with `streamLayers`), one byte per
// cell marking cells the model surface passes through, the surfaces of one batch (see
// `LayerOptions::batchCrossings`) and one set of eq. 13 cells per layer of the batch. Measured (2
// cores, Release): 400×300×400 cells (21 M inside), analytic field, 101 layers, 21–26 M output
// vertices and 42–51 M triangles: 18 s (flat layers) to 21 s (curved layers), half of it for the
// thickness statistics, before batching (one batch held all surfaces: peak memory about 3× the
// output meshes, which take ~24 bytes per triangle). Bunny end to end: tests/bench/README.md §3.
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/layers/layer_simplification.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

struct LayerOptions {
  double layerThickness = 1.5;  ///< h, mm (> 0); the workbench's default too
  bool clipToSolid = true;      ///< clip surfaces to the model and project rims onto it
  int maxLayers = 100000;       ///< safety limit; more layers is an InvalidInput error
  /// Vertices per layer measured for `thicknessToPrevious` (evenly spaced runs of consecutive
  /// vertices); 0 measures every vertex, < 0 skips the measurement (samples = 0). Measuring a
  /// layer builds a hierarchy over the previous one (~0.4 µs per triangle) and costs one
  /// closest-point query per sample (~3 µs on flat, ~25 µs on curved layers).
  int thicknessSamples = 4096;
  /// Layers are built in batches of consecutive levels that together cross at most this many
  /// cubes of the dual grid (a level crossing more is a batch of its own). A crossed cube gives
  /// up to 12 triangles (about 4–5 on the bunny's curved layers, 8 on layers parallel to a grid
  /// face), and a batch holds its unclipped and clipped surfaces, vertex keys and merge maps at
  /// once, about 140 bytes per triangle. 0: automatic, max(kMinBatchCrossings, cells /
  /// kCellsPerBatchCrossing), which keeps a batch at or below ~6–7 bytes per grid cell, so the
  /// layer stage (6 bytes per cell of volume arrays plus one batch) stays below the nominal
  /// VoxelizeOptions::bytesPerCell the memory budget is checked with (tests/bench/README.md,
  /// "Large thin-walled part"). Results do not depend on it.
  std::size_t batchCrossings = 0;
  /// Simplification of each clipped surface (off by default; ε = 0.05·L); the thickness,
  /// area and components are those of the simplified surfaces.
  LayerSimplificationOptions simplification;
};

/// Smallest automatic batch, in crossed cubes.
inline constexpr std::size_t kMinBatchCrossings = std::size_t{1} << 18;
/// Grid cells per crossed cube of an automatic batch (see LayerOptions::batchCrossings).
inline constexpr std::size_t kCellsPerBatchCrossing = 256;

struct ThicknessStats {
  std::size_t samples = 0;  ///< vertices measured (0 if there is no previous surface)
  double min = 0.0, mean = 0.0, max = 0.0;  ///< mm
};

struct LayerSurface {
  int index = 0;       ///< i, 1-based
  double level = 0.0;  ///< i·h, mm
  /// Part frame, indexed (neighbouring triangles share vertices), no face ids. Triangles are
  /// oriented with normals towards increasing distance (away from the start surface).
  TriMesh mesh;
  double area = 0.0;  ///< mm²
  std::size_t components = 0;
  ThicknessStats thicknessToPrevious;
};

/// The paper's voxel set S_i (eq. 13).
struct VoxelLayerSet {
  int index = 0;
  double level = 0.0;
  std::vector<std::size_t> cells;  ///< linear cell indices into the grid
};

/// Everything about a layer but its geometry (what `streamLayers` keeps).
struct LayerSummary {
  int index = 0;       ///< i, 1-based
  double level = 0.0;  ///< i·h, mm
  std::size_t vertices = 0, triangles = 0;
  std::size_t fullResolutionTriangles = 0;  ///< before simplification (= triangles if off)
  double area = 0.0;                        ///< mm²
  std::size_t components = 0;
  ThicknessStats thicknessToPrevious;
  std::size_t voxelSetSize = 0;  ///< cells of S_i
};

/// Diagnostics of one `extractLayers` call.
struct LayerExtractionStats {
  std::size_t extendedCells = 0;            ///< outside cells given extrapolated field values
  std::size_t partialFits = 0;              ///< of those, fitted with a rank-deficient gradient
  std::size_t nearestFallbacks = 0;         ///< of those, given the nearest reached value
  std::size_t exactDistanceQueries = 0;     ///< vertices clipped with an exact signed distance
  std::size_t rimVertices = 0;              ///< vertices created on the model surface by clipping
  double simplificationTolerance = 0.0;     ///< ε used, mm (0: simplification off)
  std::size_t fullResolutionTriangles = 0;  ///< all layers, after clipping, before simplifying
  std::size_t simplifiedTriangles = 0;      ///< all layers after simplifying (= the above if off)
  std::size_t layersKeptFull = 0;      ///< layers left unsimplified (not a 2-manifold, see header)
  double simplificationSeconds = 0.0;  ///< wall time of the "simplifying layers" stage
  double seconds = 0.0;                ///< wall time of the call
};

struct LayersResult {
  std::vector<LayerSurface> surfaces;    ///< layers 1..n, in order (a layer may be empty)
  std::vector<VoxelLayerSet> voxelSets;  ///< S_1..S_n, in order
  LayerExtractionStats stats;
  /// Per layer, in order: counts, area, components, thickness, |S_i|. Filled by extractLayers and
  /// by runLayerJob in both forms (the streaming one leaves `surfaces` and `voxelSets` empty).
  std::vector<LayerSummary> summaries;
  /// Grid cross-checks of the batching: the number of batches and the most cubes one crossed.
  std::size_t batches = 0, largestBatchCrossings = 0;
};

/// Receives the layers of `streamLayers` as they are finished, on the calling thread, in this
/// order: `begin` once, then for each batch the surfaces of its levels (increasing index) followed
/// by their voxel sets (increasing index), so all surfaces and all sets each arrive in order
/// 1..n. Whatever a method throws ends the extraction with that exception.
class LayerSink {
 public:
  virtual ~LayerSink() = default;
  /// @param layerCount      n, the number of layers that will follow (may be 0)
  /// @param voxelSetSizes   |S_i| for i = 1..n (what `acceptVoxelSet` will receive)
  /// @param geometry        the grid the voxel sets' cell indices refer to
  virtual void begin(int layerCount, const std::vector<std::size_t>& voxelSetSizes,
                     const GridGeometry& geometry) = 0;
  /// Layer i with its statistics; the sink may keep or drop it.
  virtual void acceptSurface(LayerSurface&& surface) = 0;
  /// S_i. `distance[n]` is the geodesic distance (mm) of every cell n of the set; the reference
  /// is valid during the call only.
  virtual void acceptVoxelSet(VoxelLayerSet&& set, const std::vector<float>& distance) = 0;
};

/// Extracts layers 1..n (see the file comment). Progress stages: "extending field", "marching
/// tetrahedra", "merging layers", "clipping layers", "simplifying layers", "measuring
/// thickness", "voxel sets".
/// @param field   geodesic field, mm, +inf for outside/unreached cells (geometry matches `grid`)
/// @param grid    the voxelized solid
/// @param model   the solid's surface, part frame (for clipping and rim projection; may be empty
///                when `clipToSolid` is false)
/// @param source  the start-surface triangles, part frame (thickness reference of layer 1; may be
///                empty, then layer 1 reports no thickness samples)
/// @throws InvalidInput for h <= 0 or non-finite, more than `maxLayers` layers (the message gives
///         the count and the smallest h that fits), a field that does not match the grid, has NaN
///         values or no reached voxel, an empty model with clipping on, or a negative or
///         non-finite simplification tolerance; Cancelled via
///         `progress` (no partial result).
LayersResult extractLayers(const DistanceField& field, const VoxelGrid& grid, const TriMesh& model,
                           const TriMesh& source, const LayerOptions& options = {},
                           Progress progress = {});

/// The same, handing every layer surface and voxel set to `sink` as soon as it is finished
/// instead of collecting them: memory holds the field (extended in place, so `field` is
/// consumed), the marks of the surface cells and one batch of layers. Progress stages as above
/// plus "counting crossings"; the batch stages repeat per batch with the overall fraction
/// increasing. Exceptions as above and whatever `sink` throws; after an exception the sink may
/// have received some layers (it must discard them).
/// @return the per-layer summaries and statistics (`surfaces` and `voxelSets` are empty)
LayersResult streamLayers(DistanceField&& field, const VoxelGrid& grid, const TriMesh& model,
                          const TriMesh& source, LayerSink& sink, const LayerOptions& options = {},
                          Progress progress = {});

}  // namespace curvedslicer
