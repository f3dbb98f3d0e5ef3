#include "curvedslicer/core/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;

namespace {

fs::path temporarySibling(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return tmp;
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

void writeFileAtomically(const fs::path& requested, const std::function<void(std::ostream&)>& write,
                         bool binary) {
  const fs::path path = resolveOutputPath(requested);
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) {
    throw IoError("output folder does not exist: '" + parent.string() +
                  "'; create it or choose another output path");
  }
  const fs::path tmp = temporarySibling(path);
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!out) {
        throw IoError("cannot create file '" + tmp.string() + "': " + std::strerror(errno) +
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
