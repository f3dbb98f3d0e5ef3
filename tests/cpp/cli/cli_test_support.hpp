// Helpers for the command-line tests: run the built `curvedslicer` binary as a subprocess and
// capture its output, read back the PLY files it writes, list output folders.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/test_paths.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

extern char** environ;

namespace curvedslicer::testing {

struct CliRun {
  int exitCode = -1;  ///< 128 + signal if the process was killed by a signal
  std::string out;
  std::string err;
};

inline std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A running `curvedslicer` process whose stdout/stderr go to files.
class CliProcess {
 public:
  explicit CliProcess(const std::vector<std::string>& args) {
    static std::atomic<unsigned> counter{0};
    captureDir_ = std::filesystem::temp_directory_path() /
                  ("curvedslicer-cli-capture-" + std::to_string(::getuid()) + "-" +
                   std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(captureDir_);
    std::filesystem::create_directories(captureDir_);
    const std::string outPath = (captureDir_ / "stdout").string();
    const std::string errPath = (captureDir_ / "stderr").string();

    std::vector<std::string> argv{cliPath().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (std::string& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&actions, 2, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    const int rc = posix_spawn(&pid_, cargv[0], &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
    }
  }
  ~CliProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
    std::error_code ec;
    std::filesystem::remove_all(captureDir_, ec);
  }
  CliProcess(const CliProcess&) = delete;
  CliProcess& operator=(const CliProcess&) = delete;

  pid_t pid() const { return pid_; }
  std::string currentErr() const { return readWholeFile(captureDir_ / "stderr"); }

  /// False once the process has exited (its status is kept for `wait`).
  bool running() {
    if (exited_ || pid_ <= 0) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      status_ = status;
      return false;
    }
    return true;
  }

  /// Waits for the process and collects its output.
  CliRun wait() {
    CliRun run;
    int status = status_;
    if (!exited_) {
      while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
      exited_ = true;
    }
    if (WIFEXITED(status)) run.exitCode = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) run.exitCode = 128 + WTERMSIG(status);
    run.out = readWholeFile(captureDir_ / "stdout");
    run.err = readWholeFile(captureDir_ / "stderr");
    return run;
  }

 private:
  pid_t pid_ = -1;
  std::filesystem::path captureDir_;
  bool exited_ = false;
  int status_ = 0;
};

/// Writes a binary STL with the given triangles (three corners each) and a declared triangle
/// count (default: the true count); `truncateTo` > 0 cuts the file to that many bytes.
inline void writeBinaryStl(const std::filesystem::path& path,
                           const std::vector<std::array<Eigen::Vector3f, 3>>& triangles,
                           long declaredCount = -1, std::size_t truncateTo = 0) {
  std::string bytes(80, ' ');
  bytes.replace(0, 22, "binary STL (test file)");
  const auto count =
      static_cast<std::uint32_t>(declaredCount < 0 ? triangles.size() : declaredCount);
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    for (const auto& v : t) bytes.append(reinterpret_cast<const char*>(v.data()), 12);
    bytes.append(2, '\0');
  }
  if (truncateTo > 0) bytes.resize(truncateTo);
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// The triangles of a mesh as corner triples (for writeBinaryStl).
inline std::vector<std::array<Eigen::Vector3f, 3>> trianglesOf(const TriMesh& mesh) {
  std::vector<std::array<Eigen::Vector3f, 3>> out;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    out.push_back({mesh.corner(t, 0).cast<float>(), mesh.corner(t, 1).cast<float>(),
                   mesh.corner(t, 2).cast<float>()});
  }
  return out;
}

/// Runs `curvedslicer ARGS...` to completion.
inline CliRun runCli(const std::vector<std::string>& args) {
  return CliProcess(args).wait();
}

/// Names of the entries of a folder (sorted); hidden entries included.
inline std::vector<std::string> listFolder(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  if (!std::filesystem::exists(dir)) return names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// A PLY file read back: every element's rows as doubles (scalar properties) and the face lists.
struct PlyData {
  std::string format;
  std::vector<std::string> comments;
  struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<std::string> properties;  ///< scalar property names, in order
    std::vector<double> values;           ///< count × properties.size() scalar values, row by row
    std::vector<std::vector<std::int64_t>> lists;  ///< the (single) list property per row

    double value(std::size_t row, std::size_t property) const {
      return values[row * properties.size() + property];
    }
  };
  std::vector<Element> elements;

  const Element* element(const std::string& name) const {
    for (const Element& e : elements)
      if (e.name == name) return &e;
    return nullptr;
  }
};

inline std::size_t plyTypeSize(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes{
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(type);
  if (it == sizes.end()) throw std::runtime_error("unknown PLY type " + type);
  return it->second;
}

inline double plyValue(const std::string& type, const unsigned char* p) {
  if (type == "char" || type == "int8") return static_cast<std::int8_t>(p[0]);
  if (type == "uchar" || type == "uint8") return p[0];
  auto load = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  if (type == "short" || type == "int16") return load(std::int16_t{});
  if (type == "ushort" || type == "uint16") return load(std::uint16_t{});
  if (type == "int" || type == "int32") return load(std::int32_t{});
  if (type == "uint" || type == "uint32") return load(std::uint32_t{});
  if (type == "float" || type == "float32") return load(float{});
  return load(double{});
}

/// Reads a binary little-endian PLY; throws std::runtime_error when the header or the size of the
/// body is inconsistent (the body must end exactly at the end of the file).
inline PlyData readBinaryPly(const std::filesystem::path& path) {
  const std::string bytes = readWholeFile(path);
  const std::size_t headerEnd = bytes.find("end_header\n");
  if (bytes.rfind("ply\n", 0) != 0 || headerEnd == std::string::npos) {
    throw std::runtime_error("not a PLY file: " + path.string());
  }
  PlyData ply;
  struct Property {
    std::string name, type, countType;
    bool list = false;
  };
  std::vector<std::vector<Property>> props;
  std::istringstream header(bytes.substr(0, headerEnd));
  std::string line;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> ply.format;
    } else if (key == "comment") {
      ply.comments.push_back(line);
    } else if (key == "element") {
      PlyData::Element e;
      words >> e.name >> e.count;
      ply.elements.push_back(e);
      props.emplace_back();
    } else if (key == "property") {
      if (props.empty()) throw std::runtime_error("property before element");
      Property p;
      std::string type;
      words >> type;
      if (type == "list") {
        p.list = true;
        words >> p.countType >> p.type >> p.name;
      } else {
        p.type = type;
        words >> p.name;
        ply.elements.back().properties.push_back(p.name);
      }
      props.back().push_back(p);
    }
  }
  if (ply.format != "binary_little_endian") throw std::runtime_error("not binary LE PLY");
  std::size_t pos = headerEnd + std::strlen("end_header\n");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  for (std::size_t e = 0; e < ply.elements.size(); ++e) {
    PlyData::Element& el = ply.elements[e];
    el.values.reserve(el.count * el.properties.size());
    for (std::size_t r = 0; r < el.count; ++r) {
      for (const Property& p : props[e]) {
        if (!p.list) {
          const std::size_t s = plyTypeSize(p.type);
          if (pos + s > bytes.size()) throw std::runtime_error("PLY body truncated");
          el.values.push_back(plyValue(p.type, data + pos));
          pos += s;
        } else {
          const std::size_t cs = plyTypeSize(p.countType);
          if (pos + cs > bytes.size()) throw std::runtime_error("PLY body truncated");
          const auto n = static_cast<std::size_t>(plyValue(p.countType, data + pos));
          pos += cs;
          const std::size_t s = plyTypeSize(p.type);
          if (pos + n * s > bytes.size()) throw std::runtime_error("PLY body truncated");
          std::vector<std::int64_t> list;
          for (std::size_t k = 0; k < n; ++k, pos += s) {
            list.push_back(static_cast<std::int64_t>(plyValue(p.type, data + pos)));
          }
          el.lists.push_back(std::move(list));
        }
      }
    }
  }
  if (pos != bytes.size()) {
    throw std::runtime_error("PLY body has " + std::to_string(bytes.size() - pos) +
                             " bytes beyond its elements");
  }
  return ply;
}

}  // namespace curvedslicer::testing
