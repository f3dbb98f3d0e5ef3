// Writing the results of a layer job into an output folder without ever leaving partial output.
//
// Everything is written into a hidden staging folder inside the output folder first; only when
// every file is complete are they moved into place (rename, same file system), after which stale
// layer files of an earlier run (layer_*.ply / layer_*.obj not rewritten now) are removed. If
// anything fails before that point the staging folder is deleted and the output folder is left
// exactly as it was (it is not even created if it did not exist).
//
// Files: layer_0001.ply … (one surface per layer, 4 digits or more), voxel_sets.ply (binary PLY
// point cloud of the eq. 13 voxel sets: float x y z in the part frame, int layer, float distance
// in mm; a voxel appears once per set that contains it) and report.json.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"

namespace curvedslicer {

/// "layer_0001.ply": the 1-based index zero-padded to max(4, digits of `layerCount`).
std::string layerFileName(int index, std::size_t layerCount, LayerFileFormat format);

/// The file names of all layer surfaces, in order.
std::vector<std::string> layerFileNames(const LayersResult& layers, LayerFileFormat format);

/// True for names an earlier run may have written: layer_<digits>.ply or layer_<digits>.obj.
bool isLayerFileName(const std::string& name);

/// Writes the voxel sets as a binary little-endian PLY point cloud (see the file comment).
/// @param field  the field the sets were taken from (cell centres and distances)
void writeVoxelSetsPly(std::ostream& out, const LayersResult& layers, const DistanceField& field);

/// The same in pieces, for sets that arrive one at a time: the header for `points` records in
/// all, then each set's records (20 bytes per cell: centre x y z in the part frame, layer index,
/// distance).
/// @param geometry  the grid the sets' cell indices refer to
/// @param distance  per-cell distances, mm, valid at the set's cells
void writeVoxelSetsPlyHeader(std::ostream& out, std::size_t points);
void appendVoxelSetPly(std::ostream& out, const VoxelLayerSet& set, const GridGeometry& geometry,
                       const std::vector<float>& distance);

/// The process id in a staging folder's name ".curvedslicer-staging-PID-N"; 0 for other names.
long stagingFolderPid(const std::string& name);

/// A set of files staged inside `dir` and published together. Nothing touches the disk until the
/// first `stage` call, which also
/// - takes the folder's lock (flock on `dir` itself), held until the commit ends or the staging
///   is discarded: one run writes into a folder at a time, another gets an IoError saying so
///   (so two runs' commits never interleave into a mixed set);
/// - clears what dead runs in `dir` left (a run killed with SIGKILL leaves its
///   ".curvedslicer-staging-PID-N"; done when no process PID exists): a staging folder without
///   a commit journal is removed (the old set was never touched); one with a journal (killed
///   while committing) has its commit finished first (the remaining moves and removals the
///   journal lists), so the folder holds the whole new set.
/// Destroying an uncommitted staging removes everything it created.
class OutputStaging {
 public:
  explicit OutputStaging(std::filesystem::path dir);
  ~OutputStaging();
  OutputStaging(const OutputStaging&) = delete;
  OutputStaging& operator=(const OutputStaging&) = delete;

  /// Writes the file `name` (a plain file name) into the staging folder through `write`, which
  /// receives the staged path and must create that file.
  /// @throws IoError if the folders cannot be created; whatever `write` throws.
  void stage(const std::string& name,
             const std::function<void(const std::filesystem::path&)>& write);

  /// Registers the file `name` and returns its path in the staging folder, for a file the caller
  /// writes itself over time (it must be complete before `commit`).
  /// @throws IoError if the folders cannot be created.
  std::filesystem::path reserve(const std::string& name);

  /// Moves every staged file into `dir` (in staging order), removes files for which
  /// `isStale(name)` holds and that were not just written, then deletes the staging folder.
  /// A target may only be a new name, a regular file or a link to one (resolveOutputPath).
  /// @throws IoError if a target is a device, FIFO, socket or folder (before anything moves), or
  ///         if a move fails (files already moved stay; the rest are removed).
  void commit(const std::function<bool(const std::string&)>& isStale = {});

  const std::filesystem::path& dir() const { return dir_; }
  const std::vector<std::string>& stagedNames() const { return names_; }
  /// Staging folders of dead runs that `stage` removed from `dir` (their names).
  const std::vector<std::string>& removedStagings() const { return removedStagings_; }

 private:
  void prepare();
  void lock();
  void removeDeadStagings();
  void discard() noexcept;
  void unlock() noexcept;

  std::filesystem::path dir_;
  std::filesystem::path staging_;
  std::vector<std::string> names_;
  std::vector<std::string> removedStagings_;
  bool createdDir_ = false;
  bool prepared_ = false;
  bool committed_ = false;
  int lockFd_ = -1;  // the open folder holding the flock, -1 when not held
};

/// Checks before any heavy work that `dir` can become an output folder: it is a folder (or does
/// not exist and its nearest existing ancestor is a folder) and is writable.
/// @throws IoError naming the folder.
void checkOutputFolder(const std::filesystem::path& dir);

}  // namespace curvedslicer
