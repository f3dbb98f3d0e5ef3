#include "curvedslicer/pipeline/option_parsing.hpp"

#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unordered_set>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"

namespace curvedslicer {

namespace {

constexpr std::string_view kStartForms =
    "use plane:bottom, plane:z=MM, faces:IDS (e.g. faces:0-9,15) or mesh:FILE";

constexpr std::string_view kIdListHelp =
    "use 0-based triangle numbers separated by commas, with ranges like 0-9,15";

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// A non-negative decimal integer that fits an int; nullopt-like -1 on failure.
long long parseId(std::string_view s) {
  if (s.empty()) return -1;
  for (char c : s) {
    if (c < '0' || c > '9') return -1;
  }
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size() || value > INT_MAX) return -2;
  return value;
}

[[noreturn]] void badIdItem(std::string_view item, std::string_view list, std::string_view why) {
  throw InvalidInput("bad face id list '" + std::string(list) + "': item '" + std::string(item) +
                     "' " + std::string(why) + "; " + std::string(kIdListHelp));
}

}  // namespace

std::vector<int> parseIdList(std::string_view text) {
  std::vector<int> ids;
  std::unordered_set<int> seen;
  const std::string_view list = trim(text);
  if (list.empty()) {
    throw InvalidInput("face id list is empty: ''; " + std::string(kIdListHelp));
  }
  std::size_t pos = 0;
  while (pos <= list.size()) {
    const std::size_t comma = list.find(',', pos);
    const std::string_view item = trim(
        list.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos));
    if (item.empty()) badIdItem(item, list, "is empty");
    const std::size_t dash = item.find('-', 1);
    long long first = 0, last = 0;
    if (item.front() == '-' || item.front() == '+') badIdItem(item, list, "has a sign");
    if (dash == std::string_view::npos) {
      first = last = parseId(item);
    } else {
      first = parseId(trim(item.substr(0, dash)));
      last = parseId(trim(item.substr(dash + 1)));
    }
    if (first == -2 || last == -2)
      badIdItem(item, list, "is larger than " + std::to_string(INT_MAX));
    if (first < 0 || last < 0) badIdItem(item, list, "is not a number or a range a-b");
    if (last < first) badIdItem(item, list, "is a reversed range (a-b needs a <= b)");
    if (ids.size() + static_cast<std::size_t>(last - first + 1) > kMaxIdListSize) {
      badIdItem(item, list,
                "makes the list longer than " + std::to_string(kMaxIdListSize) + " ids");
    }
    for (long long id = first; id <= last; ++id) {
      if (seen.insert(static_cast<int>(id)).second) ids.push_back(static_cast<int>(id));
    }
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return ids;
}

StartSurfaceSpec parseStartSurfaceSpec(std::string_view text) {
  StartSurfaceSpec spec;
  spec.text = std::string(text);
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos) {
    throw InvalidInput("unknown start surface: '" + spec.text + "'; " + std::string(kStartForms));
  }
  const std::string kind = lower(trim(text.substr(0, colon)));
  const std::string_view argument = trim(text.substr(colon + 1));
  if (kind == "plane") {
    const std::string arg = lower(argument);
    if (arg == "bottom") {
      spec.surface = StartSurface::buildPlate();
      return spec;
    }
    if (arg.rfind("z=", 0) == 0) {
      const double z = parseLength(trim(argument.substr(2)), "start plane height z");
      if (!std::isfinite(z)) {
        throw InvalidInput("start plane height z must be finite: '" + spec.text +
                           "'; pass a height in mm such as plane:z=0");
      }
      spec.surface = StartSurface::horizontalPlane(z);
      return spec;
    }
    throw InvalidInput("unknown start plane: '" + spec.text +
                       "'; use plane:bottom (the build plate under the model) or plane:z=MM");
  }
  if (kind == "faces") {
    spec.surface = StartSurface::faces(parseIdList(argument));
    return spec;
  }
  if (kind == "mesh") {
    if (argument.empty()) {
      throw InvalidInput("start surface mesh file is missing: '" + spec.text +
                         "'; use mesh:FILE with an STL or OBJ surface");
    }
    spec.surface.kind = StartSurface::Kind::Mesh;
    spec.meshFile = std::filesystem::path(std::string(argument));
    return spec;
  }
  throw InvalidInput("unknown start surface kind: '" + spec.text + "'; " +
                     std::string(kStartForms));
}

StartSurface loadStartSurface(const StartSurfaceSpec& spec) {
  if (spec.surface.kind != StartSurface::Kind::Mesh) return spec.surface;
  try {
    return StartSurface::surface(readMesh(spec.meshFile));
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("start surface mesh: ") + e.what());
  }
}

namespace {

double parseNumber(std::string_view text, std::string_view what, std::string_view hint) {
  const std::string s(trim(text));
  char* end = nullptr;
  const double value = s.empty() ? 0.0 : std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) {
    throw InvalidInput(std::string(what) + " is not a number: '" + std::string(text) + "'; pass " +
                       std::string(hint));
  }
  return value;
}

}  // namespace

double parseLength(std::string_view text, std::string_view what) {
  return parseNumber(text, what, "a length in mm such as 1.5");
}

double parseAngle(std::string_view text, std::string_view what) {
  return parseNumber(text, what, "an angle in degrees such as 30");
}

namespace {

/// "a,b,c[,…]" with exactly `count` finite numbers.
std::vector<double> parseNumberList(std::string_view text, std::size_t count, std::string_view what,
                                    std::string_view example) {
  std::vector<double> values;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = text.find(',', begin);
    const std::string_view item = text.substr(
        begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin);
    const double v = parseLength(item, what);
    if (!std::isfinite(v)) {
      throw InvalidInput(std::string(what) + " needs finite numbers: '" + std::string(text) +
                         "'; pass e.g. " + std::string(example));
    }
    values.push_back(v);
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  if (values.size() != count) {
    throw InvalidInput(std::string(what) + " needs " + std::to_string(count) +
                       " comma-separated numbers: '" + std::string(text) + "'; pass e.g. " +
                       std::string(example));
  }
  return values;
}

}  // namespace

void parseBeadWidthRange(std::string_view text, PlannerOptions& options) {
  if (text == "off") {
    options.widthMin = options.widthMax = 1.0;
    return;
  }
  const std::vector<double> range = parseNumberList(
      text, 2, "--bead-width-range", "0.7,1.3 (fractions of the bead spacing) or off");
  options.widthMin = range[0];
  options.widthMax = range[1];
}

namespace {

std::string formatNumbers(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "%.9g,%.9g,%.9g", v.x(), v.y(), v.z());
  return buffer;
}

}  // namespace

InitialCurveSpec parseInitialCurveSpec(std::string_view text) {
  InitialCurveSpec spec;
  spec.text = std::string(text);
  if (text == "boundary") return spec;
  if (text.rfind("plane:", 0) == 0) {
    const auto v = parseNumberList(text.substr(6), 6, "initial plane", "plane:0,0,0,1,0,0");
    spec.curve.kind = InitialCurveKind::Plane;
    spec.curve.planePoint = Vec3(v[0], v[1], v[2]);
    spec.curve.planeNormal = Vec3(v[3], v[4], v[5]);
    return spec;
  }
  if (text.rfind("mesh:", 0) == 0 && text.size() > 5) {
    spec.curve.kind = InitialCurveKind::Surface;
    spec.meshFile = std::filesystem::path(std::string(text.substr(5)));
    return spec;
  }
  throw InvalidInput("unknown initial curve: '" + spec.text +
                     "'; choose boundary, plane:X,Y,Z,NX,NY,NZ or mesh:FILE");
}

InitialCurve loadInitialCurve(const InitialCurveSpec& spec) {
  if (spec.curve.kind != InitialCurveKind::Surface) return spec.curve;
  InitialCurve curve = spec.curve;
  try {
    curve.surface = cleanMesh(readMesh(spec.meshFile)).mesh;
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("initial surface mesh: ") + e.what());
  }
  return curve;
}

void parseThinWallEdge(std::string_view text, ThinWallOptions& options) {
  if (text == "lowest") {
    options.edge = WallEdgeKind::LowestAlongAxis;
    options.axis = Vec3::UnitZ();
  } else if (text.rfind("lowest:", 0) == 0) {
    const auto v = parseNumberList(text.substr(7), 3, "thin-wall axis", "lowest:0,0,1");
    options.edge = WallEdgeKind::LowestAlongAxis;
    options.axis = Vec3(v[0], v[1], v[2]);
  } else if (text.rfind("nearest:", 0) == 0) {
    const auto v = parseNumberList(text.substr(8), 3, "thin-wall edge point", "nearest:0,0,0");
    options.edge = WallEdgeKind::NearestToPoint;
    options.point = Vec3(v[0], v[1], v[2]);
  } else {
    throw InvalidInput("unknown thin-wall edge: '" + std::string(text) +
                       "'; choose lowest, lowest:AX,AY,AZ or nearest:X,Y,Z");
  }
}

std::string formatThinWallEdge(const ThinWallOptions& options) {
  const std::string kind(toString(options.edge));
  if (options.edge == WallEdgeKind::NearestToPoint)
    return kind + ":" + formatNumbers(options.point);
  if (options.axis == Vec3::UnitZ()) return kind;
  return kind + ":" + formatNumbers(options.axis);
}

LayerFileFormat parseLayerFileFormat(std::string_view name) {
  const std::string n = lower(trim(name));
  if (n == "ply") return LayerFileFormat::Ply;
  if (n == "obj") return LayerFileFormat::Obj;
  throw InvalidInput("unknown layer file format: '" + std::string(name) + "'; use ply or obj");
}

std::string_view toString(LayerFileFormat format) {
  return format == LayerFileFormat::Ply ? "ply" : "obj";
}

}  // namespace curvedslicer
