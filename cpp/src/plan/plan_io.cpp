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
/// Version 2's point fields; version 1 has the first 9 (no width).
constexpr std::array<const char*, 10> kPointFields = {"x",  "y",  "z",  "nx", "ny",
                                                      "nz", "vx", "vy", "vz", "w"};
constexpr std::size_t kVersion1PointFields = 9;
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

/// A measured coverage reads back: finite numbers, shares in [0, 1], no negative area or size.
void checkCoverage(const LayerCoverage& c, const std::string& where, const std::string& origin) {
  if (!c.measured) return;
  const std::initializer_list<std::pair<const char*, double>> values = {
      {"/area_mm2", c.area},
      {"/void_share", c.voidShare},
      {"/overlap_share", c.overlapShare},
      {"/bead_width_mm", c.beadWidth}};
  for (const auto& [key, value] : values) {
    checkFinite(value, where + key, origin);
    const bool share = key[1] != 'a' && key[1] != 'b';
    if (value < 0.0 || (share && value > 1.0)) {
      throw InvalidInput(origin + ": " + where + key +
                         " is out of range: " + std::to_string(value) + "; " + kRegenerate);
    }
  }
  for (const CoverageVoid& v : c.voids) {
    for (int i = 0; i < 3; ++i) checkFinite(v.centre[i], where + "/voids centre", origin);
    checkFinite(v.area, where + "/voids area", origin);
    checkFinite(v.size, where + "/voids size", origin);
    if (v.area < 0.0 || v.size < 0.0) {
      throw InvalidInput(origin + ": " + where + "/voids has a negative area or size; " +
                         kRegenerate);
    }
  }
}

/// Layers are deposited in the plan's order, so their heights (distance from the start surface)
/// grow: a plan of several Jobs deposited one after the other starts again at each Job's first
/// layer, but a plan whose heights fall more often than they rise runs top-down (its layers
/// reversed) and would be welded from the top, into the air.
void checkLayerOrder(const Plan& plan, const std::string& origin) {
  const auto mm = [](double value) {
    std::string text;
    appendNumber(text, value);
    return text;
  };
  std::size_t rising = 0, falling = 0;
  for (std::size_t l = 1; l < plan.layers.size(); ++l) {
    const double step = plan.layers[l].height - plan.layers[l - 1].height;
    (step < 0.0 ? falling : rising) += step != 0.0 ? 1 : 0;
  }
  if (falling > rising) {
    throw InvalidInput(origin + ": the layer heights fall from /layers/0 (" +
                       mm(plan.layers.front().height) + " mm) to the last layer (" +
                       mm(plan.layers.back().height) + " mm) on " + std::to_string(falling) +
                       " of " + std::to_string(plan.layers.size() - 1) +
                       " steps: the layers are in reverse order, and would be deposited from the "
                       "top down; " +
                       kRegenerate);
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
    checkCoverage(layer.coverage, pointer(l) + "/coverage", origin);
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
      checkFinite(path.dwell, pointer(l, k) + "/dwell_s", origin);
      if (path.dwell < 0.0) {
        throw InvalidInput(origin + ": " + pointer(l, k) + "/dwell_s is negative: " +
                           std::to_string(path.dwell) + "; " + kRegenerate);
      }
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
        checkFinite(q.width, where + " width", origin);
        if (q.width < 0.0) {
          throw InvalidInput(origin + ": " + where +
                             " width is negative: " + std::to_string(q.width) + "; " + kRegenerate);
        }
      }
    }
  }
  checkLayerOrder(plan, origin);
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

/// What the layers' reading depends on: the file's version and, for version 1, the width every
/// point gets (the bead spacing).
struct FileFormat {
  int version = Plan::kFormatVersion;
  double beadSpacing = 0.0;
  std::size_t pointFields() const {
    return version == 1 ? kVersion1PointFields : kPointFields.size();
  }
};

std::string describePointFields(std::size_t count) {
  std::string text;
  for (std::size_t i = 0; i < count; ++i) text += (i ? " " : "") + std::string(kPointFields[i]);
  return text;
}

PathPoint readPoint(const Reader& r, const Json& row, const std::string& at,
                    const FileFormat& format) {
  const std::size_t n = format.pointFields();
  if (!row.is_array() || row.size() != n) {
    r.fail(at, (row.is_array() ? "has " + std::to_string(row.size()) + " numbers"
                               : "is a " + std::string(row.type_name())) +
                   ": expected " + std::to_string(n) + " (" + describePointFields(n) + ")");
  }
  std::array<double, 10> v{};
  for (std::size_t c = 0; c < n; ++c) v[c] = r.number(row[c], at + "/" + std::to_string(c));
  PathPoint p;
  p.position = Vec3(v[0], v[1], v[2]);
  p.normal = Vec3(v[3], v[4], v[5]);
  p.deposition = Vec3(v[6], v[7], v[8]);
  p.width = format.version == 1 ? format.beadSpacing : v[9];
  if (p.width < 0.0) r.fail(at + "/9", "must not be negative: " + abbreviateJson(row[9]));
  return p;
}

PlanPath readPath(const Reader& r, const Json& j, const std::string& where,
                  const FileFormat& format) {
  if (format.version == 1) {
    r.expectKeys(j, where, {"layer", "index", "closed", "length_mm", "points"});
  } else {
    r.expectKeys(j, where, {"layer", "index", "closed", "length_mm", "points"}, {"dwell_s"});
  }
  PlanPath path;
  path.layer = r.integer(j["layer"], where + "/layer");
  path.index = r.integer(j["index"], where + "/index");
  path.closed = r.boolean(j["closed"], where + "/closed");
  path.length = r.number(j["length_mm"], where + "/length_mm");
  if (j.contains("dwell_s")) path.dwell = r.nonNegative(j["dwell_s"], where + "/dwell_s");
  const Json& points = r.array(j["points"], where + "/points");
  path.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    path.points.push_back(readPoint(r, points[i], where + "/points/" + std::to_string(i), format));
  }
  return path;
}

/// A share of the layer area: a number in [0, 1].
double readShare(const Reader& r, const Json& j, const std::string& where) {
  const double v = r.nonNegative(j, where);
  if (v > 1.0) r.fail(where, "is " + abbreviateJson(j) + ": expected a share in [0, 1]");
  return v;
}

Vec3 readVec3(const Reader& r, const Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) r.fail(where, "must be an array of 3 numbers");
  return Vec3(r.number(j[0], where + "/0"), r.number(j[1], where + "/1"),
              r.number(j[2], where + "/2"));
}

LayerCoverage readCoverage(const Reader& r, const Json& j, const std::string& where) {
  r.expectKeys(j, where,
               {"area_mm2", "void_share", "overlap_share", "bead_width_mm", "arc_starts", "voids"});
  LayerCoverage c;
  c.measured = true;
  c.area = r.nonNegative(j["area_mm2"], where + "/area_mm2");
  c.voidShare = readShare(r, j["void_share"], where + "/void_share");
  c.overlapShare = readShare(r, j["overlap_share"], where + "/overlap_share");
  c.beadWidth = r.nonNegative(j["bead_width_mm"], where + "/bead_width_mm");
  c.arcStarts = static_cast<std::size_t>(r.integer(j["arc_starts"], where + "/arc_starts"));
  const Json& voids = r.array(j["voids"], where + "/voids");
  for (std::size_t i = 0; i < voids.size(); ++i) {
    const std::string at = where + "/voids/" + std::to_string(i);
    r.expectKeys(voids[i], at, {"area_mm2", "centre_mm", "size_mm"});
    CoverageVoid v;
    v.area = r.nonNegative(voids[i]["area_mm2"], at + "/area_mm2");
    v.centre = readVec3(r, voids[i]["centre_mm"], at + "/centre_mm");
    v.size = r.nonNegative(voids[i]["size_mm"], at + "/size_mm");
    c.voids.push_back(v);
  }
  return c;
}

PlanLayer readLayer(const Reader& r, const Json& j, const std::string& where,
                    const FileFormat& format) {
  if (format.version == 1) {
    r.expectKeys(j, where, {"index", "height_mm", "surface", "warnings", "paths"});
  } else {
    r.expectKeys(j, where, {"index", "height_mm", "surface", "warnings", "paths"}, {"coverage"});
  }
  PlanLayer layer;
  layer.index = r.integer(j["index"], where + "/index");
  layer.height = r.nonNegative(j["height_mm"], where + "/height_mm");
  layer.surface = r.string(j["surface"], where + "/surface");
  const Json& warnings = r.array(j["warnings"], where + "/warnings");
  for (std::size_t i = 0; i < warnings.size(); ++i) {
    layer.warnings.push_back(r.string(warnings[i], where + "/warnings/" + std::to_string(i)));
  }
  if (j.contains("coverage")) layer.coverage = readCoverage(r, j["coverage"], where + "/coverage");
  const Json& paths = r.array(j["paths"], where + "/paths");
  layer.paths.reserve(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    layer.paths.push_back(readPath(r, paths[i], where + "/paths/" + std::to_string(i), format));
  }
  return layer;
}

/// The "version" (1 or 2), checked before anything else so that a newer file gets the "update"
/// message, not a key error.
int readVersion(const Reader& r, const Json& doc) {
  if (!doc.is_object()) r.fail("", "must be a JSON object, found " + std::string(doc.type_name()));
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
  return static_cast<int>(version);
}

/// The bead coverage parameters (version 2, each optional).
void readCoverageParameters(const Reader& r, const Json& pj, PlanParameters& p) {
  if (pj.contains("min_feature_width_mm")) {
    const double w = r.number(pj["min_feature_width_mm"], "/parameters/min_feature_width_mm");
    if (!(w > 0.0)) {
      r.fail("/parameters/min_feature_width_mm",
             "is " + abbreviateJson(pj["min_feature_width_mm"]) + ": expected a width > 0 mm");
    }
    p.minFeatureWidth = w;
  }
  if (pj.contains("bead_width_range")) {
    const std::string where = "/parameters/bead_width_range";
    const Json& range = pj["bead_width_range"];
    if (!range.is_array() || range.size() != 2) r.fail(where, "must be an array of 2 numbers");
    const std::array<double, 2> v = {r.number(range[0], where + "/0"),
                                     r.number(range[1], where + "/1")};
    if (!(v[0] > 0.0 && v[0] <= 1.0 && v[1] >= 1.0)) {
      r.fail(where, "is " + abbreviateJson(range) +
                        ": expected [min, max] fractions of the bead spacing, 0 < min <= 1 <= max");
    }
    p.beadWidthRange = v;
  }
  if (pj.contains("connect_insets")) {
    p.connectInsets = r.boolean(pj["connect_insets"], "/parameters/connect_insets");
  }
  if (pj.contains("fill_gaps")) {
    p.fillGaps = r.boolean(pj["fill_gaps"], "/parameters/fill_gaps");
  }
  if (pj.contains("min_gap_area_mm2")) {
    const double a = r.number(pj["min_gap_area_mm2"], "/parameters/min_gap_area_mm2");
    if (!(a > 0.0)) {
      r.fail("/parameters/min_gap_area_mm2",
             "is " + abbreviateJson(pj["min_gap_area_mm2"]) + ": expected an area > 0 mm²");
    }
    p.minGapArea = a;
  }
  if (pj.contains("corner_overdeposit_mm")) {
    p.cornerOverdeposit =
        r.number(pj["corner_overdeposit_mm"], "/parameters/corner_overdeposit_mm");
  }
  if (pj.contains("corner_fill_angle_deg")) {
    const double a = r.number(pj["corner_fill_angle_deg"], "/parameters/corner_fill_angle_deg");
    if (!(a > 0.0 && a < 180.0)) {
      r.fail("/parameters/corner_fill_angle_deg", "is " +
                                                      abbreviateJson(pj["corner_fill_angle_deg"]) +
                                                      ": expected an angle in (0, 180) degrees");
    }
    p.cornerFillAngle = a;
  }
}

PlanParameters readParameters(const Reader& r, const Json& pj, int version) {
  const std::initializer_list<const char*> required = {
      "layer_thickness_mm", "voxel_size_mm", "bead_spacing_mm", "point_spacing_mm",
      "fit_tolerance_mm",   "field_method",  "surface_method",  "initial_curve"};
  if (version == 1) {
    r.expectKeys(pj, "/parameters", required, {"narrow_strips", "corner_angle_deg"});
  } else {
    r.expectKeys(
        pj, "/parameters", required,
        {"narrow_strips", "deposition_direction", "corner_angle_deg", "min_feature_width_mm",
         "bead_width_range", "connect_insets", "fill_gaps", "min_gap_area_mm2",
         "corner_overdeposit_mm", "corner_fill_angle_deg", "layer_tolerance_mm"});
  }
  PlanParameters p;
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
  if (pj.contains("deposition_direction")) {
    p.depositionDirection =
        r.string(pj["deposition_direction"], "/parameters/deposition_direction");
    if (p.depositionDirection != "growth" && p.depositionDirection != "nearest") {
      r.fail("/parameters/deposition_direction", "is " +
                                                     abbreviateJson(Json(p.depositionDirection)) +
                                                     ": expected \"growth\" or \"nearest\"");
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
  readCoverageParameters(r, pj, p);
  if (pj.contains("layer_tolerance_mm")) {
    p.layerTolerance = r.nonNegative(pj["layer_tolerance_mm"], "/parameters/layer_tolerance_mm");
  }
  return p;
}

void readPointFields(const Reader& r, const Json& fields, const FileFormat& format) {
  const std::size_t n = format.pointFields();
  bool fieldsOk = fields.size() == n;
  for (std::size_t i = 0; fieldsOk && i < fields.size(); ++i) {
    fieldsOk = fields[i].is_string() && fields[i].get<std::string>() == kPointFields[i];
  }
  if (!fieldsOk) {
    std::string expected = "[";
    for (std::size_t i = 0; i < n; ++i)
      expected += (i ? ",\"" : "\"") + std::string(kPointFields[i]) + "\"";
    r.fail("/point_fields", "is " + abbreviateJson(fields) + ": expected " + expected + "]" +
                                (format.version == 1 ? " (version 1)" : ""));
  }
}

Plan readDocument(const Reader& r, const Json& doc) {
  FileFormat format;
  format.version = readVersion(r, doc);
  r.expectKeys(doc, "",
               {"format", "version", "model", "start", "parameters", "point_fields", "layers"});
  Plan plan;
  plan.model = r.string(doc["model"], "/model");
  plan.start = r.string(doc["start"], "/start");
  plan.parameters = readParameters(r, doc["parameters"], format.version);
  format.beadSpacing = plan.parameters.beadSpacing;
  readPointFields(r, r.array(doc["point_fields"], "/point_fields"), format);
  const Json& layers = r.array(doc["layers"], "/layers");
  plan.layers.reserve(layers.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    plan.layers.push_back(readLayer(r, layers[i], "/layers/" + std::to_string(i), format));
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
  // An optional parameter: written after a comma when present, absent otherwise.
  const auto appendOptionalNumber = [&out](const char* key, const std::optional<double>& value) {
    if (!value) return;
    out += ",\n";
    appendKey(out, "    ", key);
    appendNumber(out, *value);
  };
  if (!p.narrowStrips.empty()) {
    out += ",\n";
    appendKey(out, "    ", "narrow_strips");
    appendString(out, p.narrowStrips, "narrow strips");
  }
  if (!p.depositionDirection.empty()) {
    out += ",\n";
    appendKey(out, "    ", "deposition_direction");
    appendString(out, p.depositionDirection, "deposition direction");
  }
  appendOptionalNumber("corner_angle_deg", p.cornerAngle);
  appendOptionalNumber("min_feature_width_mm", p.minFeatureWidth);
  if (p.beadWidthRange) {
    out += ",\n";
    appendKey(out, "    ", "bead_width_range");
    out += "[";
    appendNumber(out, (*p.beadWidthRange)[0]);
    out += ", ";
    appendNumber(out, (*p.beadWidthRange)[1]);
    out += "]";
  }
  if (p.connectInsets) {
    out += ",\n";
    appendKey(out, "    ", "connect_insets");
    out += *p.connectInsets ? "true" : "false";
  }
  if (p.fillGaps) {
    out += ",\n";
    appendKey(out, "    ", "fill_gaps");
    out += *p.fillGaps ? "true" : "false";
  }
  appendOptionalNumber("min_gap_area_mm2", p.minGapArea);
  appendOptionalNumber("corner_overdeposit_mm", p.cornerOverdeposit);
  appendOptionalNumber("corner_fill_angle_deg", p.cornerFillAngle);
  appendOptionalNumber("layer_tolerance_mm", p.layerTolerance);
  out += "\n  },\n";
}

/// The width written for a point: its own, or the bead spacing where it is 0.
double widthOf(const PathPoint& q, double beadSpacing) {
  return q.width > 0.0 ? q.width : beadSpacing;
}

/// One path object, followed by "," unless it is the layer's last.
void appendPath(std::string& out, const PlanPath& path, double beadSpacing, bool last) {
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
  if (path.dwell > 0.0) {
    appendKey(out, "          ", "dwell_s");
    appendNumber(out, path.dwell);
    out += ",\n";
  }
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
    out += ", ";
    appendNumber(out, widthOf(q, beadSpacing));
    out += qi + 1 < path.points.size() ? "],\n" : "]\n";
  }
  out += "          ]\n";
  out += last ? "        }\n" : "        },\n";
}

void appendVec3(std::string& out, const Vec3& v) {
  out += "[";
  for (int c = 0; c < 3; ++c) {
    if (c) out += ", ";
    appendNumber(out, v[c]);
  }
  out += "]";
}

/// `"coverage": {...},` of a layer whose coverage was measured; one line per void patch.
void appendCoverage(std::string& out, const LayerCoverage& c) {
  appendKey(out, "      ", "coverage");
  out += "{\"area_mm2\": ";
  appendNumber(out, c.area);
  out += ", \"void_share\": ";
  appendNumber(out, c.voidShare);
  out += ", \"overlap_share\": ";
  appendNumber(out, c.overlapShare);
  out += ", \"bead_width_mm\": ";
  appendNumber(out, c.beadWidth);
  out += ", \"arc_starts\": " + std::to_string(c.arcStarts) + ", \"voids\": [";
  for (std::size_t i = 0; i < c.voids.size(); ++i) {
    out += i ? ",\n" : "\n";
    out += "        {\"area_mm2\": ";
    appendNumber(out, c.voids[i].area);
    out += ", \"centre_mm\": ";
    appendVec3(out, c.voids[i].centre);
    out += ", \"size_mm\": ";
    appendNumber(out, c.voids[i].size);
    out += "}";
  }
  out += c.voids.empty() ? "]},\n" : "\n      ]},\n";
}

/// One layer object (index `li`), followed by "," unless it is the plan's last.
void appendLayer(std::string& out, const PlanLayer& layer, std::size_t li, double beadSpacing,
                 bool last) {
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
  if (layer.coverage.measured) appendCoverage(out, layer.coverage);
  appendKey(out, "      ", "paths");
  out += layer.paths.empty() ? "[]\n" : "[\n";
  for (std::size_t pi = 0; pi < layer.paths.size(); ++pi) {
    appendPath(out, layer.paths[pi], beadSpacing, pi + 1 == layer.paths.size());
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
    appendLayer(out, plan.layers[li], li, plan.parameters.beadSpacing,
                li + 1 == plan.layers.size());
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
  // a regular file of at most 4 GiB: a FIFO, a device or a folder is refused unread
  return parsePlanJson(readInputFile(path, "plan file", kMaxPlanFileBytes), path.string());
}

// ---- CSV ----------------------------------------------------------------------------------------

std::string formatPlanCsv(const Plan& plan) {
  checkPlan(plan, "plan");
  std::string out = "layer,path,point,closed,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz,w_mm\n";
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
        out += ',';
        appendNumber(out, widthOf(q, plan.parameters.beadSpacing));
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
