#include "curvedslicer/pipeline/layer_output.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_set>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;

namespace {

template <typename T>
void appendLittleEndian(std::string& buffer, T value) {
  static_assert(sizeof(T) == 4);
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, 4);
  if constexpr (std::endian::native == std::endian::big) {
    bits =
        ((bits & 0xffu) << 24) | ((bits & 0xff00u) << 8) | ((bits >> 8) & 0xff00u) | (bits >> 24);
  }
  char bytes[4];
  std::memcpy(bytes, &bits, 4);
  buffer.append(bytes, 4);
}

std::string errorText(const std::error_code& ec) {
  return ec.message();
}

}  // namespace

long stagingFolderPid(const std::string& name) {
  constexpr std::string_view prefix = ".curvedslicer-staging-";
  if (name.rfind(prefix, 0) != 0) return 0;
  const std::string_view rest = std::string_view(name).substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == 0 || dash == std::string_view::npos || dash > 9 || dash + 1 == rest.size()) return 0;
  const auto digits = [](std::string_view t) {
    return std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(rest.substr(0, dash)) || !digits(rest.substr(dash + 1))) return 0;
  return std::stol(std::string(rest.substr(0, dash)));
}

std::string layerFileName(int index, std::size_t layerCount, LayerFileFormat format) {
  const std::size_t width = std::max<std::size_t>(4, std::to_string(layerCount).size());
  std::string digits = std::to_string(index);
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  return "layer_" + digits + "." + std::string(toString(format));
}

std::vector<std::string> layerFileNames(const LayersResult& layers, LayerFileFormat format) {
  std::vector<std::string> names;
  names.reserve(layers.surfaces.size());
  for (const LayerSurface& s : layers.surfaces) {
    names.push_back(layerFileName(s.index, layers.surfaces.size(), format));
  }
  return names;
}

bool isLayerFileName(const std::string& name) {
  constexpr std::string_view prefix = "layer_";
  if (name.size() <= prefix.size() + 4 || name.rfind(prefix, 0) != 0) return false;
  const std::string_view ext = std::string_view(name).substr(name.size() - 4);
  if (ext != ".ply" && ext != ".obj") return false;
  const std::string_view digits =
      std::string_view(name).substr(prefix.size(), name.size() - prefix.size() - 4);
  return !digits.empty() &&
         std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

void writeVoxelSetsPlyHeader(std::ostream& out, std::size_t points) {
  out << "ply\n"
      << "format binary_little_endian 1.0\n"
      << "comment curvedslicer voxel layer sets S_i (paper eq. 13): voxel centres in the part "
         "frame (mm), layer index i, geodesic distance (mm)\n"
      << "element vertex " << points << "\n"
      << "property float x\n"
      << "property float y\n"
      << "property float z\n"
      << "property int layer\n"
      << "property float distance\n"
      << "end_header\n";
}

void appendVoxelSetPly(std::ostream& out, const VoxelLayerSet& set, const GridGeometry& geometry,
                       const std::vector<float>& distance) {
  std::string buffer;
  constexpr std::size_t kRecord = 20;
  constexpr std::size_t kFlushBytes = std::size_t{1} << 20;
  buffer.reserve(std::min(kFlushBytes, set.cells.size() * kRecord) + kRecord);
  for (std::size_t n : set.cells) {
    const Vec3 p = geometry.centerInPart(n);
    appendLittleEndian(buffer, static_cast<float>(p.x()));
    appendLittleEndian(buffer, static_cast<float>(p.y()));
    appendLittleEndian(buffer, static_cast<float>(p.z()));
    appendLittleEndian(buffer, static_cast<std::int32_t>(set.index));
    appendLittleEndian(buffer, distance[n]);
    if (buffer.size() >= kFlushBytes) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

void writeVoxelSetsPly(std::ostream& out, const LayersResult& layers, const DistanceField& field) {
  std::size_t points = 0;
  for (const VoxelLayerSet& set : layers.voxelSets) points += set.cells.size();
  writeVoxelSetsPlyHeader(out, points);
  for (const VoxelLayerSet& set : layers.voxelSets) {
    appendVoxelSetPly(out, set, field.geometry, field.distance);
  }
}

// ---- OutputStaging ----------------------------------------------------------------------------

namespace {

/// The commit journal in a staging folder: written (atomically) before the first move, one line
/// per step: "move NAME" (staging -> folder) and "remove NAME" (a stale file of the folder).
constexpr const char* kCommitJournal = ".commit";

/// Finishes the commit of a dead run from its journal: moves the staged files still there and
/// removes the stale files listed (regular files only).
void finishCommit(const fs::path& staging, const fs::path& dir) {
  std::ifstream in(staging / kCommitJournal);
  std::string line;
  std::error_code ec;
  while (std::getline(in, line)) {
    const std::size_t space = line.find(' ');
    if (space == std::string::npos) continue;
    const std::string step = line.substr(0, space), name = line.substr(space + 1);
    if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..") {
      continue;  // the journal names plain files of this folder only
    }
    if (step == "move" && fs::is_regular_file(staging / name, ec)) {
      fs::rename(staging / name, dir / name, ec);
    } else if (step == "remove" && fs::is_regular_file(fs::symlink_status(dir / name, ec))) {
      fs::remove(dir / name, ec);
    }
  }
}

}  // namespace

OutputStaging::OutputStaging(fs::path dir) : dir_(std::move(dir)) {}

OutputStaging::~OutputStaging() {
  if (!committed_) discard();
}

void OutputStaging::prepare() {
  if (prepared_) return;
  std::error_code ec;
  if (fs::exists(dir_, ec)) {
    if (!fs::is_directory(dir_, ec)) {
      throw IoError("output path exists and is not a folder: '" + dir_.string() +
                    "'; choose a folder path");
    }
  } else {
    fs::create_directories(dir_, ec);
    if (ec) {
      throw IoError("cannot create output folder '" + dir_.string() + "': " + errorText(ec) +
                    "; check the path and its permissions");
    }
    createdDir_ = true;
  }
  lock();
  removeDeadStagings();
  static std::atomic<unsigned> counter{0};
  staging_ = dir_ / (".curvedslicer-staging-" + std::to_string(::getpid()) + "-" +
                     std::to_string(counter++));
  fs::create_directory(staging_, ec);
  if (ec) {
    const std::string message = "cannot create a staging folder in '" + dir_.string() +
                                "': " + errorText(ec) + "; check that the folder is writable";
    discard();
    throw IoError(message);
  }
  prepared_ = true;
}

void OutputStaging::lock() {
  lockFd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lockFd_ < 0) {
    throw IoError("cannot open the output folder '" + dir_.string() + "': " + std::strerror(errno) +
                  "; check its permissions");
  }
  if (::flock(lockFd_, LOCK_EX | LOCK_NB) == 0) return;
  const int error = errno;
  unlock();
  if (error != EWOULDBLOCK) {
    throw IoError("cannot lock the output folder '" + dir_.string() + "': " + std::strerror(error) +
                  "; choose a folder on a local file system");
  }
  // the other run's staging folder names its process
  std::string who;
  std::error_code ec;
  for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const long pid = stagingFolderPid(it->path().filename().string());
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) == 0)
      who = " (process " + std::to_string(pid) + ")";
  }
  throw IoError("another curvedslicer run" + who + " is writing into the output folder '" +
                dir_.string() +
                "' now; wait for it to finish, or choose another output folder (-o)");
}

void OutputStaging::unlock() noexcept {
  if (lockFd_ >= 0) ::close(lockFd_);  // closing the folder releases the flock
  lockFd_ = -1;
}

void OutputStaging::removeDeadStagings() {
  std::error_code ec;
  std::vector<fs::path> dead;
  for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const long pid = stagingFolderPid(it->path().filename().string());
    if (pid <= 0 || !it->is_directory(ec) || it->is_symlink(ec)) continue;
    // kill(pid, 0) fails with ESRCH only when no such process exists (EPERM: it exists).
    if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) dead.push_back(it->path());
  }
  for (const fs::path& p : dead) {
    if (fs::exists(p / kCommitJournal, ec)) finishCommit(p, dir_);
    fs::remove_all(p, ec);
    if (!ec) removedStagings_.push_back(p.filename().string());
  }
}

void OutputStaging::stage(const std::string& name,
                          const std::function<void(const fs::path&)>& write) {
  prepare();
  write(staging_ / name);
  names_.push_back(name);
}

fs::path OutputStaging::reserve(const std::string& name) {
  prepare();
  names_.push_back(name);
  return staging_ / name;
}

void OutputStaging::commit(const std::function<bool(const std::string&)>& isStale) {
  std::error_code ec;
  // Every target is checked before the first move: never onto a device, FIFO, socket or folder.
  std::vector<fs::path> targets;
  for (const std::string& name : names_) targets.push_back(resolveOutputPath(dir_ / name));
  // the stale files, and the journal of the whole commit: a run killed while moving leaves it
  // for the next run into this folder to finish (removeDeadStagings)
  std::vector<fs::path> stale;
  if (isStale) {
    const std::unordered_set<std::string> fresh(names_.begin(), names_.end());
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (!fresh.count(name) && isStale(name) && it->is_regular_file(ec)) {
        stale.push_back(it->path());
      }
    }
  }
  std::ostringstream journal;
  for (const std::string& name : names_) journal << "move " << name << '\n';
  for (const fs::path& p : stale) journal << "remove " << p.filename().string() << '\n';
  if (prepared_) writeTextFileAtomically(staging_ / kCommitJournal, journal.str());
  for (std::size_t k = 0; k < names_.size(); ++k) {
    fs::rename(staging_ / names_[k], targets[k], ec);
    if (ec) {
      throw IoError("cannot move '" + (staging_ / names_[k]).string() + "' to '" +
                    targets[k].string() + "': " + errorText(ec) + "; check the output folder");
    }
  }
  committed_ = true;
  for (const fs::path& p : stale) fs::remove(p, ec);
  if (prepared_) fs::remove_all(staging_, ec);
  unlock();
}

void OutputStaging::discard() noexcept {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  if (createdDir_) fs::remove(dir_, ec);  // only succeeds while empty
  unlock();
}

void checkOutputFolder(const fs::path& dir) {
  if (dir.empty()) {
    throw IoError("output folder is empty: ''; pass a folder path such as out/part");
  }
  std::error_code ec;
  fs::path existing = dir;
  while (!fs::exists(existing, ec)) {
    if (!existing.has_parent_path() || existing.parent_path() == existing) {
      existing = fs::path(".");
      break;
    }
    existing = existing.parent_path();
  }
  if (!fs::is_directory(existing, ec)) {
    if (existing == dir) {
      throw IoError("output path exists and is not a folder: '" + dir.string() +
                    "'; choose a folder path");
    }
    throw IoError("cannot create output folder '" + dir.string() + "': '" + existing.string() +
                  "' is not a folder; choose another output path");
  }
  if (::access(existing.c_str(), W_OK | X_OK) != 0) {
    throw IoError("output folder is not writable: '" + existing.string() + "' (" +
                  std::strerror(errno) + "); choose a writable folder");
  }
}

}  // namespace curvedslicer
