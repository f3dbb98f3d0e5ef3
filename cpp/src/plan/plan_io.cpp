#include "curvedslicer/plan/plan_io.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <istream>
#include <ostream>
#include <sstream>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "core/bounded_json.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

using Json = nlohmann::json;

constexpr double kUnitTolerance = 1e-6;
constexpr std::array<const char*, 9> kPointFields = {"x",  "y",  "z",  "nx", "ny",
                                                     "nz", "vx", "vy", "vz"};
constexpr const char* kRegenerate = "regenerate the plan with `curvedslicer plan`";

// ---- number and string formatting ---------------------------------------------------------------

/// Shortest text that reads back to the same double; -0 is written as 0 (JSON readers turn "-0"
/// into the integer 0, which would not round-trip).
void appendNumber(std::string& out, double value) {
  if (value == 0.0) value = 0.0;
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  if (ec != std::errc()) throw NumericalFailure("cannot format number; report this as a bug");
  out.append(buffer, end);
}

void appendString(std::string& out, const std::string& text, const std::string& where) {
  try {
    out += Json(text).dump();
  } catch (const Json::exception&) {
    throw InvalidInput("plan " + where + " is not valid UTF-8: '" + text +
                       "'; use UTF-8 text for names and file paths");
  }
}

std::string pointer(int layer) {
  return "/layers/" + std::to_string(layer);
}
std::string pointer(int layer, int path) {
  return pointer(layer) + "/paths/" + std::to_string(path);
}
std::string pointer(int layer, int path, int point) {
  return pointer(layer, path) + "/points/" + std::to_string(point);
}

// ---- semantic checks (shared by writer and reader) ---------------------------------------------

void checkFinite(double value, const std::string& where, const std::string& origin) {
  if (!std::isfinite(value)) {
    throw InvalidInput(origin + ": " + where + " is not a finite number: " + std::to_string(value) +
                       "; " + kRegenerate);
  }
}

void checkUnit(const Vec3& v, const std::string& where, const std::string& origin) {
  for (int i = 0; i < 3; ++i) checkFinite(v[i], where, origin);
  const double n = v.norm();
  if (std::abs(n - 1.0) > kUnitTolerance) {
    std::ostringstream msg;
    msg.precision(17);
    msg << origin << ": " << where << " is not a unit vector: length " << n << "; " << kRegenerate;
    throw InvalidInput(msg.str());
  }
}

void checkPlan(const Plan& plan, const std::string& origin) {
  const PlanParameters& p = plan.parameters;
  const std::initializer_list<std::pair<const char*, double>> params = {
      {"/parameters/layer_thickness_mm", p.layerThickness},
      {"/parameters/voxel_size_mm", p.voxelSize},
      {"/parameters/bead_spacing_mm", p.beadSpacing},
      {"/parameters/point_spacing_mm", p.pointSpacing},
      {"/parameters/fit_tolerance_mm", p.fitTolerance}};
  for (const auto& [where, value] : params) checkFinite(value, where, origin);
  for (std::size_t li = 0; li < plan.layers.size(); ++li) {
    const PlanLayer& layer = plan.layers[li];
    const int l = static_cast<int>(li);
    if (layer.index != l) {
      throw InvalidInput(origin + ": " + pointer(l) + "/index is " + std::to_string(layer.index) +
                         ": expected its position " + std::to_string(l) + "; " + kRegenerate);
    }
    checkFinite(layer.height, pointer(l) + "/height_mm", origin);
    for (std::size_t pi = 0; pi < layer.paths.size(); ++pi) {
      const PlanPath& path = layer.paths[pi];
      const int k = static_cast<int>(pi);
      if (path.layer != l) {
        throw InvalidInput(origin + ": " + pointer(l, k) + "/layer is " +
                           std::to_string(path.layer) + ": expected the layer's index " +
                           std::to_string(l) + "; " + kRegenerate);
      }
      if (path.index != k) {
        throw InvalidInput(origin + ": " + pointer(l, k) + "/index is " +
                           std::to_string(path.index) + ": expected its position " +
                           std::to_string(k) + "; " + kRegenerate);
      }
      checkFinite(path.length, pointer(l, k) + "/length_mm", origin);
      if (path.length < 0.0) {
        throw InvalidInput(origin + ": " + pointer(l, k) + "/length_mm is negative: " +
                           std::to_string(path.length) + "; " + kRegenerate);
      }
      if (path.points.size() < 2) {
        throw InvalidInput(origin + ": " + pointer(l, k) + " has " +
                           std::to_string(path.points.size()) +
                           " point(s): a path needs at least 2; " + kRegenerate);
      }
      for (std::size_t qi = 0; qi < path.points.size(); ++qi) {
        const PathPoint& q = path.points[qi];
        const std::string where = pointer(l, k, static_cast<int>(qi));
        for (int i = 0; i < 3; ++i) checkFinite(q.position[i], where + " position", origin);
        checkUnit(q.normal, where + " normal", origin);
        checkUnit(q.deposition, where + " deposition direction", origin);
      }
    }
  }
}

// ---- JSON reading helpers -----------------------------------------------------------------------

class Reader {
 public:
  explicit Reader(std::string origin) : origin_(std::move(origin)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InvalidInput(origin_ + ": " + (where.empty() ? std::string("the document") : where) +
                       " " + what + "; " + kRegenerate);
  }

  /// Checks that `j` is an object with exactly `keys` (all required, no others).
  /// `keys` must all be present; `optional` ones may be; nothing else.
  void expectKeys(const Json& j, const std::string& where, std::initializer_list<const char*> keys,
                  std::initializer_list<const char*> optional = {}) const {
    if (!j.is_object()) fail(where, "must be a JSON object, found " + std::string(j.type_name()));
    for (const char* key : keys) {
      if (!j.contains(key)) fail(where, std::string("lacks the key \"") + key + "\"");
    }
    for (const auto& item : j.items()) {
      bool known = false;
      for (const char* key : keys) known = known || item.key() == key;
      for (const char* key : optional) known = known || item.key() == key;
      if (!known) fail(where, "has an unknown key " + abbreviateJson(Json(item.key())));
    }
  }

  double number(const Json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, "must be a number, found " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, "is not a finite number");
    return v;
  }

  /// A number >= 0 (the schema's "minimum": 0).
  double nonNegative(const Json& j, const std::string& where) const {
    const double v = number(j, where);
    if (v < 0.0) fail(where, "must not be negative: " + abbreviateJson(j));
    return v;
  }

  int integer(const Json& j, const std::string& where) const {
    if (!j.is_number_integer()) {
      fail(where,
           "must be an integer, found " + std::string(j.type_name()) + " " + abbreviateJson(j));
    }
    const auto v = j.get<long long>();
    if (v < 0 || v > 2147483647LL) fail(where, "is out of range: " + std::to_string(v));
    return static_cast<int>(v);
  }

  std::string string(const Json& j, const std::string& where) const {
    if (!j.is_string()) fail(where, "must be a string, found " + std::string(j.type_name()));
    return j.get<std::string>();
  }

  bool boolean(const Json& j, const std::string& where) const {
    if (!j.is_boolean()) fail(where, "must be true or false, found " + std::string(j.type_name()));
    return j.get<bool>();
  }

  const Json& array(const Json& j, const std::string& where) const {
    if (!j.is_array()) fail(where, "must be an array, found " + std::string(j.type_name()));
    return j;
  }

  const std::string& origin() const { return origin_; }

 private:
  std::string origin_;
};

PlanPath readPath(const Reader& r, const Json& j, const std::string& where) {
  r.expectKeys(j, where, {"layer", "index", "closed", "length_mm", "points"});
  PlanPath path;
  path.layer = r.integer(j["layer"], where + "/layer");
  path.index = r.integer(j["index"], where + "/index");
  path.closed = r.boolean(j["closed"], where + "/closed");
  path.length = r.number(j["length_mm"], where + "/length_mm");
  const Json& points = r.array(j["points"], where + "/points");
  path.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string at = where + "/points/" + std::to_string(i);
    const Json& row = points[i];
    if (!row.is_array() || row.size() != kPointFields.size()) {
      r.fail(at, (row.is_array() ? "has " + std::to_string(row.size()) + " numbers"
                                 : "is a " + std::string(row.type_name())) +
                     ": expected 9 (x y z nx ny nz vx vy vz)");
    }
    std::array<double, 9> v{};
    for (std::size_t c = 0; c < v.size(); ++c)
      v[c] = r.number(row[c], at + "/" + std::to_string(c));
    PathPoint p;
    p.position = Vec3(v[0], v[1], v[2]);
    p.normal = Vec3(v[3], v[4], v[5]);
    p.deposition = Vec3(v[6], v[7], v[8]);
    path.points.push_back(p);
  }
  return path;
}

PlanLayer readLayer(const Reader& r, const Json& j, const std::string& where) {
  r.expectKeys(j, where, {"index", "height_mm", "surface", "warnings", "paths"});
  PlanLayer layer;
  layer.index = r.integer(j["index"], where + "/index");
  layer.height = r.nonNegative(j["height_mm"], where + "/height_mm");
  layer.surface = r.string(j["surface"], where + "/surface");
  const Json& warnings = r.array(j["warnings"], where + "/warnings");
  for (std::size_t i = 0; i < warnings.size(); ++i) {
    layer.warnings.push_back(r.string(warnings[i], where + "/warnings/" + std::to_string(i)));
  }
  const Json& paths = r.array(j["paths"], where + "/paths");
  layer.paths.reserve(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    layer.paths.push_back(readPath(r, paths[i], where + "/paths/" + std::to_string(i)));
  }
  return layer;
}

Plan readDocument(const Reader& r, const Json& doc) {
  if (!doc.is_object()) r.fail("", "must be a JSON object, found " + std::string(doc.type_name()));
  // Format and version first, so that a newer file gets the "update" message, not a key error.
  if (!doc.contains("format") || !doc["format"].is_string() ||
      doc["format"].get<std::string>() != kPlanFormatName) {
    throw InvalidInput(
        r.origin() + ": not a CurvedSlicer plan (\"format\" is " +
        (doc.contains("format") ? abbreviateJson(doc["format"]) : std::string("missing")) +
        ", expected \"" + std::string(kPlanFormatName) +
        "\"); pass a plan.json written by `curvedslicer plan`");
  }
  if (!doc.contains("version") || !doc["version"].is_number_integer()) {
    r.fail("/version", "must be an integer");
  }
  const auto version = doc["version"].get<long long>();
  if (version > Plan::kFormatVersion) {
    throw InvalidInput(r.origin() + ": plan format version not supported: " +
                       std::to_string(version) + " (this build reads up to " +
                       std::to_string(Plan::kFormatVersion) + "); update curvedslicer to read it");
  }
  if (version < 1) r.fail("/version", "is not a valid version: " + std::to_string(version));
  r.expectKeys(doc, "",
               {"format", "version", "model", "start", "parameters", "point_fields", "layers"});
  Plan plan;
  plan.model = r.string(doc["model"], "/model");
  plan.start = r.string(doc["start"], "/start");
  const Json& pj = doc["parameters"];
  r.expectKeys(pj, "/parameters",
               {"layer_thickness_mm", "voxel_size_mm", "bead_spacing_mm", "point_spacing_mm",
                "fit_tolerance_mm", "field_method", "surface_method", "initial_curve"},
               {"narrow_strips", "corner_angle_deg"});
  PlanParameters& p = plan.parameters;
  p.layerThickness = r.nonNegative(pj["layer_thickness_mm"], "/parameters/layer_thickness_mm");
  p.voxelSize = r.nonNegative(pj["voxel_size_mm"], "/parameters/voxel_size_mm");
  p.beadSpacing = r.nonNegative(pj["bead_spacing_mm"], "/parameters/bead_spacing_mm");
  p.pointSpacing = r.nonNegative(pj["point_spacing_mm"], "/parameters/point_spacing_mm");
  p.fitTolerance = r.nonNegative(pj["fit_tolerance_mm"], "/parameters/fit_tolerance_mm");
  p.fieldMethod = r.string(pj["field_method"], "/parameters/field_method");
  p.surfaceMethod = r.string(pj["surface_method"], "/parameters/surface_method");
  p.initialCurve = r.string(pj["initial_curve"], "/parameters/initial_curve");
  if (pj.contains("narrow_strips")) {
    p.narrowStrips = r.string(pj["narrow_strips"], "/parameters/narrow_strips");
    if (p.narrowStrips != "centre_bead" && p.narrowStrips != "overlap") {
      r.fail("/parameters/narrow_strips", "is " + abbreviateJson(Json(p.narrowStrips)) +
                                              ": expected \"centre_bead\" or \"overlap\"");
    }
  }
  if (pj.contains("corner_angle_deg")) {
    const double angle = r.number(pj["corner_angle_deg"], "/parameters/corner_angle_deg");
    if (!(angle > 0.0 && angle <= 180.0)) {
      r.fail("/parameters/corner_angle_deg", "is " + abbreviateJson(pj["corner_angle_deg"]) +
                                                 ": expected an angle in (0, 180] degrees");
    }
    p.cornerAngle = angle;
  }
  const Json& fields = r.array(doc["point_fields"], "/point_fields");
  bool fieldsOk = fields.size() == kPointFields.size();
  for (std::size_t i = 0; fieldsOk && i < fields.size(); ++i) {
    fieldsOk = fields[i].is_string() && fields[i].get<std::string>() == kPointFields[i];
  }
  if (!fieldsOk) {
    r.fail("/point_fields", "is " + abbreviateJson(fields) +
                                ": expected [\"x\",\"y\",\"z\",\"nx\",\"ny\",\"nz\",\"vx\",\"vy\","
                                "\"vz\"]");
  }
  const Json& layers = r.array(doc["layers"], "/layers");
  plan.layers.reserve(layers.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    plan.layers.push_back(readLayer(r, layers[i], "/layers/" + std::to_string(i)));
  }
  checkPlan(plan, r.origin());
  return plan;
}

void writeToStream(std::ostream& out, const std::string& text) {
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw IoError("writing the plan failed (disk full or stream closed); nothing usable");
}

}  // namespace

void validatePlan(const Plan& plan) {
  checkPlan(plan, "plan");
}

// ---- JSON writing -------------------------------------------------------------------------------

namespace {

/// `indent"name": ` (a key of a hand-formatted JSON object).
void appendKey(std::string& out, const char* indent, const char* name) {
  out += indent;
  out += '"';
  out += name;
  out += "\": ";
}

void appendParameters(std::string& out, const PlanParameters& p) {
  appendKey(out, "  ", "parameters");
  out += "{\n";
  const std::initializer_list<std::pair<const char*, double>> numbers = {
      {"layer_thickness_mm", p.layerThickness},
      {"voxel_size_mm", p.voxelSize},
      {"bead_spacing_mm", p.beadSpacing},
      {"point_spacing_mm", p.pointSpacing},
      {"fit_tolerance_mm", p.fitTolerance}};
  for (const auto& [name, value] : numbers) {
    appendKey(out, "    ", name);
    appendNumber(out, value);
    out += ",\n";
  }
  appendKey(out, "    ", "field_method");
  appendString(out, p.fieldMethod, "field method");
  out += ",\n";
  appendKey(out, "    ", "surface_method");
  appendString(out, p.surfaceMethod, "surface method");
  out += ",\n";
  appendKey(out, "    ", "initial_curve");
  appendString(out, p.initialCurve, "initial curve");
  if (!p.narrowStrips.empty()) {
    out += ",\n";
    appendKey(out, "    ", "narrow_strips");
    appendString(out, p.narrowStrips, "narrow strips");
  }
  if (p.cornerAngle) {
    out += ",\n";
    appendKey(out, "    ", "corner_angle_deg");
    appendNumber(out, *p.cornerAngle);
  }
  out += "\n  },\n";
}

/// One path object, followed by "," unless it is the layer's last.
void appendPath(std::string& out, const PlanPath& path, bool last) {
  out += "        {\n";
  appendKey(out, "          ", "layer");
  out += std::to_string(path.layer) + ",\n";
  appendKey(out, "          ", "index");
  out += std::to_string(path.index) + ",\n";
  appendKey(out, "          ", "closed");
  out += path.closed ? "true,\n" : "false,\n";
  appendKey(out, "          ", "length_mm");
  appendNumber(out, path.length);
  out += ",\n";
  appendKey(out, "          ", "points");
  out += "[\n";
  for (std::size_t qi = 0; qi < path.points.size(); ++qi) {
    const PathPoint& q = path.points[qi];
    out += "            [";
    const Vec3* vs[3] = {&q.position, &q.normal, &q.deposition};
    for (int v = 0; v < 3; ++v) {
      for (int c = 0; c < 3; ++c) {
        if (v || c) out += ", ";
        appendNumber(out, (*vs[v])[c]);
      }
    }
    out += qi + 1 < path.points.size() ? "],\n" : "]\n";
  }
  out += "          ]\n";
  out += last ? "        }\n" : "        },\n";
}

/// One layer object (index `li`), followed by "," unless it is the plan's last.
void appendLayer(std::string& out, const PlanLayer& layer, std::size_t li, bool last) {
  out += "    {\n";
  appendKey(out, "      ", "index");
  out += std::to_string(layer.index) + ",\n";
  appendKey(out, "      ", "height_mm");
  appendNumber(out, layer.height);
  out += ",\n";
  appendKey(out, "      ", "surface");
  appendString(out, layer.surface, pointer(static_cast<int>(li)) + "/surface");
  out += ",\n";
  appendKey(out, "      ", "warnings");
  out += "[";
  for (std::size_t w = 0; w < layer.warnings.size(); ++w) {
    if (w) out += ", ";
    appendString(out, layer.warnings[w], pointer(static_cast<int>(li)) + "/warnings");
  }
  out += "],\n";
  appendKey(out, "      ", "paths");
  out += layer.paths.empty() ? "[]\n" : "[\n";
  for (std::size_t pi = 0; pi < layer.paths.size(); ++pi) {
    appendPath(out, layer.paths[pi], pi + 1 == layer.paths.size());
  }
  if (!layer.paths.empty()) out += "      ]\n";
  out += last ? "    }\n" : "    },\n";
}

}  // namespace

std::string formatPlanJson(const Plan& plan) {
  checkPlan(plan, "plan");
  std::string out;
  out.reserve(256 + plan.pointCount() * 200);
  out += "{\n";
  appendKey(out, "  ", "format");
  appendString(out, std::string(kPlanFormatName), "format");
  out += ",\n";
  appendKey(out, "  ", "version");
  out += std::to_string(Plan::kFormatVersion) + ",\n";
  appendKey(out, "  ", "model");
  appendString(out, plan.model, "model");
  out += ",\n";
  appendKey(out, "  ", "start");
  appendString(out, plan.start, "start");
  out += ",\n";
  appendParameters(out, plan.parameters);
  appendKey(out, "  ", "point_fields");
  out += "[";
  for (std::size_t i = 0; i < kPointFields.size(); ++i) {
    out += i ? ", \"" : "\"";
    out += kPointFields[i];
    out += '"';
  }
  out += "],\n";
  appendKey(out, "  ", "layers");
  out += plan.layers.empty() ? "[]\n" : "[\n";
  for (std::size_t li = 0; li < plan.layers.size(); ++li) {
    appendLayer(out, plan.layers[li], li, li + 1 == plan.layers.size());
  }
  if (!plan.layers.empty()) out += "  ]\n";
  out += "}\n";
  return out;
}

void writePlanJson(std::ostream& out, const Plan& plan) {
  writeToStream(out, formatPlanJson(plan));
}

void writePlanJson(const std::filesystem::path& path, const Plan& plan) {
  const std::string text = formatPlanJson(plan);
  writeTextFileAtomically(path, text);
}

// ---- JSON reading -------------------------------------------------------------------------------

Plan parsePlanJson(std::string_view text, std::string_view origin) {
  const Reader reader{std::string(origin)};
  const Json doc = parseBoundedJson(text, std::string(origin) + " is not valid JSON",
                                    "pass a plan.json written by `curvedslicer plan`");
  try {
    return readDocument(reader, doc);
  } catch (const Json::exception& e) {
    // The checks above should leave the library nothing to object to; name the file if it does.
    throw InvalidInput(std::string(origin) + ": unexpected content (" +
                       std::string(e.what()).substr(0, 200) + "); " + kRegenerate);
  }
}

Plan readPlanJson(std::istream& in, std::string_view origin) {
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError("reading " + std::string(origin) + " failed; check the file");
  return parsePlanJson(buffer.str(), origin);
}

Plan readPlanJson(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw IoError("cannot open plan file '" + path.string() +
                  "'; check the path and its permissions");
  }
  return readPlanJson(in, path.string());
}

// ---- CSV ----------------------------------------------------------------------------------------

std::string formatPlanCsv(const Plan& plan) {
  checkPlan(plan, "plan");
  std::string out = "layer,path,point,closed,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz\n";
  out.reserve(out.size() + plan.pointCount() * 180);
  for (const PlanLayer& layer : plan.layers) {
    for (const PlanPath& path : layer.paths) {
      for (std::size_t qi = 0; qi < path.points.size(); ++qi) {
        const PathPoint& q = path.points[qi];
        out += std::to_string(path.layer) + ',' + std::to_string(path.index) + ',' +
               std::to_string(qi) + (path.closed ? ",1" : ",0");
        const Vec3* vs[3] = {&q.position, &q.normal, &q.deposition};
        for (const Vec3* v : vs) {
          for (int c = 0; c < 3; ++c) {
            out += ',';
            appendNumber(out, (*v)[c]);
          }
        }
        out += '\n';
      }
    }
  }
  return out;
}

void writePlanCsv(std::ostream& out, const Plan& plan) {
  writeToStream(out, formatPlanCsv(plan));
}

void writePlanCsv(const std::filesystem::path& path, const Plan& plan) {
  writeTextFileAtomically(path, formatPlanCsv(plan));
}

}  // namespace curvedslicer
