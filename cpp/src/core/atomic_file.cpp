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

}  // namespace

void writeFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& write,
                         bool binary) {
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
