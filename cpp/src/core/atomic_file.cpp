#include "curvedslicer/core/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include <signal.h>
#include <unistd.h>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTmpMarker = ".tmp-";

/// The longest file name the folder's file system takes (NAME_MAX, usually 255 bytes).
std::size_t nameLimit(const fs::path& folder) {
  const long limit = ::pathconf(folder.c_str(), _PC_NAME_MAX);
  return limit > 0 ? static_cast<std::size_t>(limit) : 255;
}

/// "NAME.tmp-PID-N" beside `path`, NAME cut so the whole stays within the file system's name
/// limit (an output name near the limit must not fail on its temporary file).
fs::path temporarySibling(const fs::path& path, const fs::path& folder) {
  static std::atomic<unsigned> counter{0};
  const std::string suffix =
      kTmpMarker + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  std::string name = path.filename().string();
  const std::size_t limit = nameLimit(folder);
  if (name.size() > limit) {
    throw InvalidInput("output file name is " + std::to_string(name.size()) +
                       " bytes long, more than the " + std::to_string(limit) +
                       " the file system allows: '" + name.substr(0, 40) +
                       "...'; choose a shorter name");
  }
  if (name.size() + suffix.size() > limit) name.resize(limit - suffix.size());
  return path.parent_path() / (name + suffix);
}

/// Removes the temporary files an earlier run writing `path` left when it was killed: siblings
/// "NAME.tmp-PID-N" (NAME: the output's name, or its start where it was cut) whose process no
/// longer exists. Files of running processes and of other outputs are left alone.
void removeDeadTemporaries(const fs::path& path, const fs::path& folder) {
  const std::string name = path.filename().string();
  const std::size_t limit = nameLimit(folder);
  std::error_code ec;
  std::vector<fs::path> dead;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    const std::size_t marker = entry.rfind(kTmpMarker);
    if (marker == std::string::npos || marker == 0 ||
        name.compare(0, marker, entry, 0, marker) != 0 ||
        (marker < name.size() && entry.size() < limit)) {
      continue;  // not this output's, or a cut name that was not cut at the limit
    }
    const std::string tail = entry.substr(marker + std::strlen(kTmpMarker));
    const std::size_t dash = tail.find('-');
    if (dash == std::string::npos || dash == 0 ||
        tail.find_first_not_of("0123456789-") != std::string::npos) {
      continue;
    }
    const long pid = std::strtol(tail.substr(0, dash).c_str(), nullptr, 10);
    // kill(pid, 0) fails with ESRCH only when no such process exists (EPERM: it exists)
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      dead.push_back(it->path());
    }
  }
  for (const fs::path& file : dead) fs::remove(file, ec);
}

/// "a FIFO (named pipe)", "a character device", ... for messages.
std::string describeFileType(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::fifo:
      return "a FIFO (named pipe)";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

}  // namespace

fs::path resolveOutputPath(const fs::path& path) {
  if (path.empty()) {
    throw InvalidInput("output path is empty: ''; pass a file path such as 'PART.JBI'");
  }
  if (!path.has_filename()) {
    throw InvalidInput("output path names no file: '" + path.string() +
                       "'; pass a file path such as '" + (path / "PART.JBI").string() + "'");
  }
  std::error_code ec;
  const fs::file_status own = fs::symlink_status(path, ec);
  if (ec || own.type() == fs::file_type::not_found) return path;
  if (fs::is_regular_file(own)) return path;
  const std::string advice =
      "; choose a regular file path (outputs never replace devices, pipes, "
      "sockets or folders)";
  if (!fs::is_symlink(own)) {
    throw IoError("output path is " + describeFileType(own.type()) + ", not a regular file: '" +
                  path.string() + "'" + advice);
  }
  const fs::file_status target = fs::status(path, ec);
  if (ec || target.type() == fs::file_type::not_found) {
    throw IoError("output path is a symbolic link to a missing file: '" + path.string() +
                  "'; remove the link or point it at an existing file");
  }
  if (!fs::is_regular_file(target)) {
    throw IoError("output path is a symbolic link to " + describeFileType(target.type()) + ": '" +
                  path.string() + "'" + advice);
  }
  const fs::path resolved = fs::canonical(path, ec);
  if (ec) {
    throw IoError("cannot resolve the symbolic link '" + path.string() + "': " + ec.message() +
                  "; check the link");
  }
  return resolved;
}

fs::path prepareTemporaryFor(const fs::path& path) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::path tmp = temporarySibling(path, folder);
  removeDeadTemporaries(path, folder);
  return tmp;
}

void writeFileAtomically(const fs::path& requested, const std::function<void(std::ostream&)>& write,
                         bool binary) {
  const fs::path path = resolveOutputPath(requested);
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) {
    throw IoError("output folder does not exist: '" + parent.string() +
                  "'; create it or choose another output path");
  }
  const fs::path tmp = prepareTemporaryFor(path);
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!out) {
        throw IoError("cannot write '" + path.string() + "' (through the temporary file '" +
                      tmp.filename().string() + "'): " + std::strerror(errno) +
                      "; check that the folder is writable");
      }
      write(out);
      out.flush();
      if (!out) {
        throw IoError("writing '" + path.string() + "' failed (disk full?); nothing was written");
      }
    }
    fs::rename(tmp, path, ec);
    if (ec) {
      throw IoError("cannot move '" + tmp.string() + "' to '" + path.string() +
                    "': " + ec.message());
    }
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

void writeTextFileAtomically(const fs::path& path, std::string_view text) {
  writeFileAtomically(path, [&](std::ostream& out) { out.write(text.data(), text.size()); });
}

void ensureDirectory(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) {
      throw IoError("output path exists and is not a folder: '" + dir.string() +
                    "'; choose a folder path");
    }
    return;
  }
  fs::create_directories(dir, ec);
  if (ec) {
    throw IoError("cannot create output folder '" + dir.string() + "': " + ec.message());
  }
}

}  // namespace curvedslicer
