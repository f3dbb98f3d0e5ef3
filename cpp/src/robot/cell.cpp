// Cell description: JSON reading with per-field validation, writing, and the default cell.
#include "curvedslicer/robot/cell.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "core/bounded_json.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using Json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

/// A JSON object being read: remembers its JSON path for messages and which keys were used.
class Field {
 public:
  Field(const Json& json, std::string path, std::string_view origin)
      : json_(json), path_(std::move(path)), origin_(origin) {}

  const std::string& path() const { return path_; }
  std::string childPath(std::string_view key) const { return path_ + "/" + std::string(key); }

  [[noreturn]] void fail(std::string_view key, std::string_view problem, std::string_view value,
                         std::string_view hint) const {
    const std::string full = key.empty() ? path_ : childPath(key);
    const std::string where = full.empty() ? std::string("/")
                              : full.size() <= 2 * kMaxEchoedJson
                                  ? full
                                  : full.substr(0, 2 * kMaxEchoedJson) + "...";
    throw InvalidInput(std::string(origin_) + ": field " + where + " " + std::string(problem) +
                       ": " + std::string(value) + "; " + std::string(hint));
  }

  bool has(std::string_view key) const {
    return json_.is_object() && json_.contains(std::string(key));
  }

  const Json& require(std::string_view key, std::string_view hint) {
    if (!json_.is_object() || !json_.contains(std::string(key))) {
      fail(key, "is missing", "(absent)", hint);
    }
    used_.insert(std::string(key));
    return json_.at(std::string(key));
  }

  Field object(std::string_view key, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_object()) fail(key, "must be an object", abbreviateJson(j), hint);
    return Field(j, childPath(key), origin_);
  }

  double number(std::string_view key, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_number()) fail(key, "must be a number", abbreviateJson(j), hint);
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(key, "must be finite", abbreviateJson(j), hint);
    return v;
  }
  double number(std::string_view key, double fallback, std::string_view hint) {
    return has(key) ? number(key, hint) : fallback;
  }
  double positive(std::string_view key, std::string_view hint) {
    const double v = number(key, hint);
    if (!(v > 0.0)) fail(key, "must be positive", formatNumber(v), hint);
    return v;
  }
  /// A number within [lo, hi] (physical bounds: larger values are unit slips or typos).
  double within(std::string_view key, double lo, double hi, std::string_view hint) {
    const double v = number(key, hint);
    if (!(v >= lo && v <= hi)) {
      fail(key, "must be between " + formatNumber(lo) + " and " + formatNumber(hi), formatNumber(v),
           hint);
    }
    return v;
  }
  double within(std::string_view key, double fallback, double lo, double hi,
                std::string_view hint) {
    return has(key) ? within(key, lo, hi, hint) : fallback;
  }
  double nonNegative(std::string_view key, std::string_view hint) {
    const double v = number(key, hint);
    if (v < 0.0) fail(key, "must not be negative", formatNumber(v), hint);
    return v;
  }
  double nonNegative(std::string_view key, double fallback, std::string_view hint) {
    const double v = number(key, fallback, hint);
    if (v < 0.0) fail(key, "must not be negative", formatNumber(v), hint);
    return v;
  }
  int integer(std::string_view key, int lo, int hi, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_number_integer()) fail(key, "must be an integer", abbreviateJson(j), hint);
    const long long v = j.get<long long>();
    if (v < lo || v > hi) {
      fail(key, "must be between " + std::to_string(lo) + " and " + std::to_string(hi),
           std::to_string(v), hint);
    }
    return static_cast<int>(v);
  }
  int integer(std::string_view key, int fallback, int lo, int hi, std::string_view hint) {
    return has(key) ? integer(key, lo, hi, hint) : fallback;
  }
  int sign(std::string_view key, std::string_view hint) {
    if (!has(key)) return 1;
    const Json& j = require(key, hint);
    if (!j.is_number_integer() || (j.get<long long>() != 1 && j.get<long long>() != -1)) {
      fail(key, "must be 1 or -1", abbreviateJson(j), hint);
    }
    return static_cast<int>(j.get<long long>());
  }
  bool boolean(std::string_view key, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_boolean()) fail(key, "must be true or false", abbreviateJson(j), hint);
    return j.get<bool>();
  }
  bool boolean(std::string_view key, bool fallback, std::string_view hint) {
    return has(key) ? boolean(key, hint) : fallback;
  }
  std::string string(std::string_view key, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_string()) fail(key, "must be a string", abbreviateJson(j), hint);
    return j.get<std::string>();
  }
  std::string string(std::string_view key, std::string fallback, std::string_view hint) {
    return has(key) ? string(key, hint) : fallback;
  }
  std::vector<double> numbers(std::string_view key, std::size_t count, std::string_view hint) {
    const Json& j = require(key, hint);
    if (!j.is_array() || j.size() != count) {
      fail(key, "must be an array of " + std::to_string(count) + " numbers", abbreviateJson(j),
           hint);
    }
    std::vector<double> out;
    for (const auto& e : j) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) {
        fail(key, "must be an array of " + std::to_string(count) + " finite numbers",
             abbreviateJson(j), hint);
      }
      out.push_back(e.get<double>());
    }
    return out;
  }
  Vec3 vec3(std::string_view key, std::string_view hint) {
    const auto v = numbers(key, 3, hint);
    return Vec3(v[0], v[1], v[2]);
  }
  Vec3 direction(std::string_view key, std::string_view hint) {
    const Vec3 v = vec3(key, hint);
    if (!(v.norm() > 1e-12))
      fail(key, "must be a non-zero vector", abbreviateJson(require(key, hint)), hint);
    return v.normalized();
  }
  template <class Enum>
  Enum choice(std::string_view key, std::initializer_list<std::pair<const char*, Enum>> options,
              std::string_view hint) {
    const std::string s = string(key, hint);
    std::string allowed;
    for (const auto& [name, value] : options) {
      if (s == name) return value;
      allowed += (allowed.empty() ? "" : ", ") + std::string(name);
    }
    fail(key, "must be one of " + allowed, abbreviateJson(Json(s)), hint);
  }
  /// Rejects keys that were not read (typos); "comment" and "sources" are documentation.
  void rejectUnknown() const {
    if (!json_.is_object()) return;
    for (const auto& item : json_.items()) {
      const std::string& key = item.key();
      if (used_.count(key) || key == "comment" || key == "sources" || key == "$schema") continue;
      fail(key, "is not a known field", abbreviateJson(Json(key)),
           "check its spelling against resources/schema/cell.schema.json");
    }
  }
  void markUsed(std::string_view key) { used_.insert(std::string(key)); }

 private:
  const Json& json_;
  std::string path_;
  std::string_view origin_;
  std::set<std::string> used_;
};

Pose readPose(Field& parent, std::string_view key, std::string_view hint) {
  Field f = parent.object(key, hint);
  const Vec3 xyz = f.vec3("xyz_mm", "give the translation in mm as [x, y, z]");
  const Vec3 rpy = f.vec3("rpy_deg", "give roll, pitch, yaw in degrees as [rx, ry, rz]");
  f.rejectUnknown();
  return makePose(xyz, rpy * kDeg);
}

/// Largest joint or positioner angle a cell may give (limits, home), degrees: ten turns.
constexpr double kMaxAxisDegrees = 3600.0;

/// Largest pulse count a controller position holds (32-bit signed).
constexpr double kMaxPulses = 2147483647.0;

/// Encoder pulses per degree of an axis: positive, and small enough that every angle within the
/// axis's limits (ten turns for an endless axis) is a 32-bit pulse count.
double readPulsesPerDegree(Field& f, std::string_view key, const JointLimit& limit, bool endless) {
  const char* hint = "give the encoder pulses per degree from the controller's parameters";
  const double ppd = f.positive(key, hint);
  const double reach =
      endless ? kMaxAxisDegrees : std::max(std::abs(limit.min), std::abs(limit.max)) / kDeg;
  if (ppd * reach > kMaxPulses) {
    f.fail(key,
           "gives pulse counts beyond the controller's 32-bit range at " + formatNumber(reach) +
               " deg",
           formatNumber(ppd), hint);
  }
  return ppd;
}

JointLimit readLimit(Field& f, std::string_view what) {
  JointLimit limit;
  const auto range = f.numbers("limits_deg", 2, "give [min, max] in degrees");
  if (std::abs(range[0]) > kMaxAxisDegrees || std::abs(range[1]) > kMaxAxisDegrees) {
    f.fail("limits_deg", "must lie within +-3600 degrees (ten turns)",
           "[" + formatNumber(range[0]) + ", " + formatNumber(range[1]) + "]",
           "give [min, max] in degrees of " + std::string(what));
  }
  if (!(range[0] < range[1])) {
    f.fail("limits_deg", "minimum must be below maximum",
           "[" + formatNumber(range[0]) + ", " + formatNumber(range[1]) + "]",
           "give [min, max] in degrees of " + std::string(what));
  }
  limit.min = range[0] * kDeg;
  limit.max = range[1] * kDeg;
  limit.maxSpeed =
      f.within("max_speed_deg_s", 0.1, 10000.0, "give the maximum joint speed in deg/s") * kDeg;
  return limit;
}

PositionerAxis readAxis(Field& parent, std::string_view key, bool mayBeEndless) {
  Field f = parent.object(key, "describe the positioner axis");
  PositionerAxis axis;
  axis.limit = readLimit(f, key);
  axis.endless = f.boolean("endless", false, "true for unlimited rotation");
  if (axis.endless && !mayBeEndless) {
    f.fail("endless", "is only allowed for the rotation axis", "true", "set it to false");
  }
  // Pulses are the Yaskawa station's unit (JBI); other controllers take degrees, so a cell may
  // leave them out (0: not known; a JBI export then stops and asks for them).
  axis.pulsesPerDegree = f.has("pulses_per_degree")
                             ? readPulsesPerDegree(f, "pulses_per_degree", axis.limit, axis.endless)
                             : 0.0;
  axis.sign = f.sign("sign", "1 if the controller turns the same way as the model axis, else -1");
  f.rejectUnknown();
  return axis;
}

/// Rounds away the last-digit noise of degree/radian conversions (1e-9 relative) and -0.
double clean(double v) {
  const double scale = std::pow(10.0, 9 - std::ceil(std::log10(std::max(std::abs(v), 1e-300))));
  const double r = std::abs(v) < 1e-12 ? 0.0 : std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

Json poseJson(const Pose& pose) {
  const Vec3 t = pose.translation();
  const Vec3 rpy = rollPitchYaw(pose.rotation()) / kDeg;
  return Json{{"xyz_mm", {clean(t.x()), clean(t.y()), clean(t.z())}},
              {"rpy_deg", {clean(rpy.x()), clean(rpy.y()), clean(rpy.z())}}};
}

Json vecJson(const Vec3& v) {
  return Json::array({clean(v.x()), clean(v.y()), clean(v.z())});
}

Json limitJson(const JointLimit& limit) {
  return Json{{"limits_deg", {clean(limit.min / kDeg), clean(limit.max / kDeg)}},
              {"max_speed_deg_s", clean(limit.maxSpeed / kDeg)}};
}

Json axisJson(const PositionerAxis& axis) {
  Json j = limitJson(axis.limit);
  j["endless"] = axis.endless;
  if (axis.pulsesPerDegree > 0.0) j["pulses_per_degree"] = axis.pulsesPerDegree;
  j["sign"] = axis.sign;
  return j;
}

constexpr const char* kJointNames[6] = {"S", "L", "U", "R", "B", "T"};

// ---- cell sections: one reader per top-level object ---------------------------------------------

RobotKinematics readKinematics(Field& r) {
  Field k = r.object("kinematics_mm", "give a1, a2, b, c1, c2, c3, c4 in mm");
  RobotKinematics kin;
  kin.a1 = k.number("a1", "S-L offset in mm");
  kin.a2 = k.number("a2", "U-axis offset in mm");
  kin.b = k.number("b", 0.0, "lateral offset in mm");
  kin.c1 = k.number("c1", "height of the L axis in mm");
  kin.c2 = k.positive("c2", "upper-arm length (L to U) in mm");
  kin.c3 = k.positive("c3", "forearm length (U to wrist centre) in mm");
  kin.c4 = k.nonNegative("c4", 0.0, "wrist centre to flange in mm");
  k.rejectUnknown();
  return kin;
}

void readJoints(Field& r, RobotDescription& robot, std::string_view origin) {
  const Json& joints = r.require("joints", "give six joints S, L, U, R, B, T");
  if (!joints.is_array() || joints.size() != 6) {
    r.fail("joints", "must be an array of 6 joint objects", abbreviateJson(joints),
           "give six joints S, L, U, R, B, T");
  }
  for (int i = 0; i < 6; ++i) {
    const Json& jj = joints[static_cast<std::size_t>(i)];
    Field jf(jj, r.childPath("joints") + "/" + std::to_string(i), origin);
    if (!jj.is_object()) jf.fail("", "must be an object", abbreviateJson(jj), "describe the joint");
    jf.string("name", kJointNames[i], "joint name");
    robot.joints[i] = readLimit(jf, kJointNames[i]);
    robot.jointSigns[i] = jf.sign("sign", "1 or -1: controller direction vs model direction");
    robot.jointOffsets[i] = jf.number("offset_deg", 0.0, "model angle at controller zero") * kDeg;
    jf.rejectUnknown();
  }
}

/// robot/controller_frame, optional in every version: when absent, the vendor's convention
/// (defaultControllerFrame) is taken and a note names it, since Cartesian program positions are
/// measured from this frame.
Pose readControllerFrame(Field& r, RobotVendor vendor, const RobotKinematics& kinematics,
                         std::vector<std::string>& notes) {
  if (r.has("controller_frame")) {
    return readPose(r, "controller_frame",
                    "give the controller's Cartesian robot frame in the robot base frame");
  }
  const Pose frame = defaultControllerFrame(vendor, kinematics);
  const double height = frame.translation().z();
  std::string taken = vendor == RobotVendor::Unknown
                          ? "no vendor named, so the robot base frame itself taken"
                          : "the " + std::string(toString(vendor)) + " convention taken: " +
                                (height != 0.0 ? "on joint 1's axis at the height of joint 2, " +
                                                     formatNumber(height) + " mm above robot/base"
                                               : std::string("the robot base frame itself"));
  notes.push_back("robot/controller_frame not given: " + taken +
                  "; Cartesian robot positions in programs are measured from it; add "
                  "robot/controller_frame to state it (see resources/cells/README.md)");
  return frame;
}

/// robot/interference, optional in every version: linear inequalities between joint angles
/// (Σ coefficients · joints ≤ max_deg); when absent none is assumed and a note says so.
std::vector<JointInequality> readInterference(Field& r, std::string_view origin,
                                              std::vector<std::string>& notes) {
  std::vector<JointInequality> limits;
  if (!r.has("interference")) {
    notes.push_back(
        "robot/interference not given: no joint interference limit assumed (only the joint "
        "ranges); add robot/interference, [] when the robot has none (see "
        "resources/cells/README.md)");
    return limits;
  }
  const Json& list = r.require("interference", "give a list of joint inequalities");
  if (!list.is_array()) {
    r.fail("interference", "must be an array", abbreviateJson(list),
           "give [{\"name\", \"coefficients\" (6 numbers), \"max_deg\"}, ...] or []");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    Field f(list[i], r.childPath("interference") + "/" + std::to_string(i), origin);
    if (!list[i].is_object()) {
      f.fail("", "must be an object", abbreviateJson(list[i]),
             "give name, coefficients (6 numbers) and max_deg");
    }
    JointInequality limit;
    limit.name = f.string("name", "name the limit, e.g. \"L/U\"");
    const auto c = f.numbers("coefficients", 6,
                             "give one coefficient per joint: sum of coefficient x joint angle "
                             "<= max_deg");
    double size = 0.0;
    for (int j = 0; j < 6; ++j) {
      limit.coefficients[j] = c[j];
      size += std::abs(c[j]);
    }
    if (!(size > 0.0)) {
      f.fail("coefficients", "must not all be zero", "[0, 0, 0, 0, 0, 0]",
             "give the joints the limit couples, e.g. [0, 1, 1, 0, 0, 0]");
    }
    limit.max = f.number("max_deg", "give the bound in degrees") * kDeg;
    f.rejectUnknown();
    limits.push_back(std::move(limit));
  }
  return limits;
}

/// A link or body radius of a cell version 3: positive and below 1 m (larger is no arm's link
/// and is taken for a unit slip).
double readRadius(Field& f, std::string_view key, std::string_view hint) {
  constexpr double kMaxRadius = 1000.0;
  const double v = f.positive(key, hint);
  if (v > kMaxRadius) {
    f.fail(key, "must be at most 1000 mm", formatNumber(v), hint);
  }
  return v;
}

/// robot/link_capsules_mm: required from cell version 3 (the arm's collision capsules); in a
/// version-2 file the arm is not checked and a note says so.
ArmEnvelope readLinks(Field& r, int version, std::vector<std::string>& notes) {
  if (version < 3) {
    if (r.has("link_capsules_mm")) {
      r.fail("link_capsules_mm", "needs cell version 3", "\"version\": " + std::to_string(version),
             "set \"version\": 3 at the top of the cell file");
    }
    notes.push_back(
        "cell version " + std::to_string(version) +
        ": robot/link_capsules_mm not given, so the robot arm is not checked for collisions "
        "(only the torch); add robot/link_capsules_mm (cell version 3, see "
        "resources/cells/README.md)");
    return {};
  }
  const char* hint =
      "give the arm's collision capsules in mm: radii column, upper_arm, elbow, forearm, wrist "
      "and upper_arm_offset (from the robot's published description; see "
      "resources/cells/README.md)";
  Field l = r.object("link_capsules_mm", hint);
  ArmEnvelope links;
  links.column = readRadius(l, "column", hint);
  links.upperArm = readRadius(l, "upper_arm", hint);
  links.upperArmOffset = l.number("upper_arm_offset", hint);
  if (std::abs(links.upperArmOffset) > 1000.0) {
    l.fail("upper_arm_offset", "must be within +-1000 mm", formatNumber(links.upperArmOffset),
           hint);
  }
  links.elbow = readRadius(l, "elbow", hint);
  links.forearm = readRadius(l, "forearm", hint);
  links.wrist = readRadius(l, "wrist", hint);
  l.rejectUnknown();
  return links;
}

RobotDescription readRobot(Field& top, std::string_view origin, RobotVendor vendor, int version,
                           std::vector<std::string>& notes) {
  Field r = top.object("robot", "describe the robot");
  RobotDescription robot;
  robot.model = r.string("model", "name the robot model");
  robot.base = readPose(r, "base", "give the robot base frame in world");
  robot.kinematics = readKinematics(r);
  robot.controllerFrame = readControllerFrame(r, vendor, robot.kinematics, notes);
  readJoints(r, robot, origin);
  robot.interference = readInterference(r, origin, notes);
  robot.links = readLinks(r, version, notes);
  robot.j3RelativeToHorizontal =
      r.boolean("j3_relative_to_horizontal", false,
                "true when the controller's J3 is the forearm's angle to the horizontal (Fanuc)");
  if (r.has("pulses_per_degree")) {
    const auto ppd = r.numbers("pulses_per_degree", 6, "give six pulses-per-degree values");
    for (std::size_t i = 0; i < ppd.size(); ++i) {
      const double v = ppd[i];
      if (!(v > 0.0)) {
        r.fail("pulses_per_degree", "must be positive", formatNumber(v),
               "copy them from the controller's parameters");
      }
      const JointLimit& limit = robot.joints[i];
      const double reach = std::max(std::abs(limit.min), std::abs(limit.max)) / kDeg;
      if (v * reach > kMaxPulses) {
        r.fail("pulses_per_degree",
               "gives joint " + std::to_string(i + 1) +
                   " pulse counts beyond the controller's 32-bit range at " + formatNumber(reach) +
                   " deg",
               formatNumber(v), "copy them from the controller's parameters");
      }
    }
    robot.pulsesPerDegree = ppd;
  }
  r.rejectUnknown();
  return robot;
}

// ---- version-2 sections (defaults and a note for version 1) ------------------------------------

/// In a version-1 file a version-2 field is refused (it would be silently ignored otherwise).
void refuseInVersion1(Field& parent, std::string_view key) {
  if (parent.has(key)) {
    parent.fail(key, "needs cell version 2", "\"version\": 1",
                "set \"version\": 2 at the top of the cell file");
  }
}

std::string describeEnvelope(const TorchEnvelope& e) {
  return "cone from the nozzle " + formatNumber(e.stickout) + " mm behind the TCP, radius " +
         formatNumber(e.radius) + " mm there and " + formatNumber(e.topRadius) +
         " mm at the top, " + formatNumber(e.length) + " mm long";
}

TorchEnvelope readEnvelope(Field& t, int version, std::vector<std::string>& notes) {
  if (version < 2) {
    refuseInVersion1(t, "envelope");
    notes.push_back("cell version 1: default torch envelope assumed (" +
                    describeEnvelope(TorchEnvelope{}) +
                    "); add tool/envelope (cell version 2) to describe your torch");
    return {};
  }
  Field e = t.object("envelope",
                     "give the torch envelope: stickout_mm, radius_mm, top_radius_mm, length_mm");
  TorchEnvelope env;
  env.stickout = e.nonNegative("stickout_mm", "TCP (wire tip) to the nozzle tip in mm");
  env.radius = e.positive("radius_mm", "outer radius of the nozzle in mm");
  env.topRadius = e.positive("top_radius_mm", "radius of the torch at the top end in mm");
  env.length = e.positive("length_mm", "nozzle tip to the top end along the torch in mm");
  e.rejectUnknown();
  return env;
}

std::string describeGeometry(const PositionerGeometry& g) {
  return "table radius " + formatNumber(g.tableRadius) + " mm, " + formatNumber(g.tableThickness) +
         " mm thick; working volume radius " + formatNumber(g.maxPartRadius) + " mm, height " +
         formatNumber(g.maxPartHeight) + " mm above the table";
}

PositionerGeometry readGeometry(Field& p, int version, std::vector<std::string>& notes) {
  if (version < 2) {
    refuseInVersion1(p, "geometry");
    notes.push_back("cell version 1: default positioner geometry assumed (" +
                    describeGeometry(PositionerGeometry{}) +
                    "); add positioner/geometry (cell version 2) for your positioner");
    return {};
  }
  Field g = p.object("geometry",
                     "give table_radius_mm, table_thickness_mm, max_part_radius_mm and "
                     "max_part_height_mm");
  PositionerGeometry geo;
  geo.tableRadius = g.positive("table_radius_mm", "radius of the table disc in mm");
  geo.tableThickness = g.positive("table_thickness_mm", "thickness of the table disc in mm");
  geo.maxPartRadius =
      g.positive("max_part_radius_mm", "largest part radius about the rotation axis in mm");
  geo.maxPartHeight = g.positive("max_part_height_mm", "largest part height over the table in mm");
  if (version >= 3) {
    geo.bodyRadius = readRadius(g, "body_radius_mm",
                                "give the radius of the positioner's body under the table (the "
                                "rotation drive housing, table underside to tilt axis) in mm");
  } else if (g.has("body_radius_mm")) {
    g.fail("body_radius_mm", "needs cell version 3", "\"version\": " + std::to_string(version),
           "set \"version\": 3 at the top of the cell file");
  } else {
    notes.push_back("cell version " + std::to_string(version) +
                    ": positioner/geometry/body_radius_mm not given, so the positioner's body "
                    "under the table is not checked for collisions; add it (cell version 3)");
  }
  g.rejectUnknown();
  return geo;
}

/// positioner/fixture: optional in version 2 (none: the part on the bare table).
FixtureGeometry readFixture(Field& p, int version, const PositionerGeometry& geometry,
                            std::string_view origin) {
  if (version < 2) {
    refuseInVersion1(p, "fixture");
    return {};
  }
  if (!p.has("fixture")) return {};
  Field f = p.object("fixture",
                     "give riser_height_mm, riser_diameter_mm, substrate_thickness_mm and "
                     "substrate_size_mm (0 for none)");
  FixtureGeometry fixture;
  fixture.riserHeight =
      f.nonNegative("riser_height_mm", 0.0, "height of the riser on the table top in mm");
  fixture.riserDiameter = f.nonNegative("riser_diameter_mm", 0.0, "diameter of the riser in mm");
  fixture.substrateThickness =
      f.nonNegative("substrate_thickness_mm", 0.0, "thickness of the substrate plate in mm");
  fixture.substrateSize =
      f.nonNegative("substrate_size_mm", 0.0, "side of the square substrate plate in mm");
  f.rejectUnknown();
  validateFixture(fixture, geometry, std::string(origin) + ": field " + f.path() + "/");
  return fixture;
}

std::string describeHome(const HomePose& h) {
  std::string joints;
  for (double q : h.robot) joints += (joints.empty() ? "" : ", ") + formatNumber(q / kDeg);
  return "robot joints [" + joints + "] deg, positioner [" + formatNumber(h.a1 / kDeg) + ", " +
         formatNumber(h.a2 / kDeg) + "] deg";
}

/// The home pose; joints and positioner angles checked against the limits read before.
HomePose readHome(Field& top, int version, const Cell& cell, std::vector<std::string>& notes) {
  if (version < 2) {
    refuseInVersion1(top, "home");
    notes.push_back("cell version 1: default home pose assumed (" + describeHome(HomePose{}) +
                    "); add home (cell version 2) with a pose clear of the table");
    return {};
  }
  Field h = top.object("home",
                       "give robot_joints_deg (6 values) and positioner_deg [tilt, "
                       "rotation] of the pose the program starts and ends at");
  HomePose home;
  const auto q = h.numbers("robot_joints_deg", 6, "give the six robot joints in degrees");
  for (int i = 0; i < 6; ++i) {
    home.robot[i] = q[i] * kDeg;
    const JointLimit& lim = cell.robot.joints[i];
    if (!lim.contains(home.robot[i])) {
      h.fail("robot_joints_deg",
             "has joint " + std::to_string(i + 1) + " (" + kJointNames[i] +
                 ") outside its limits [" + formatNumber(lim.min / kDeg) + ", " +
                 formatNumber(lim.max / kDeg) + "] deg",
             formatNumber(q[i]), "give a home pose within the robot's joint limits");
    }
  }
  if (const JointInequality* limit = violatedInterference(cell.robot, home.robot)) {
    h.fail("robot_joints_deg", "violates the robot's interference limit " + limit->name,
           abbreviateJson(Json(q)), "give a home pose that satisfies robot/interference");
  }
  const auto a = h.numbers("positioner_deg", 2, "give [tilt, rotation] in degrees");
  for (double v : a) {
    if (std::abs(v) > kMaxAxisDegrees) {
      h.fail("positioner_deg", "must lie within +-3600 degrees (ten turns)", formatNumber(v),
             "give the home angles in degrees");
    }
  }
  home.a1 = a[0] * kDeg;
  home.a2 = a[1] * kDeg;
  const PositionerAxis* axes[2] = {&cell.positioner.tilt, &cell.positioner.rotation};
  for (int i = 0; i < 2; ++i) {
    const PositionerAxis& axis = *axes[i];
    if (!axis.endless && !axis.limit.contains(a[i] * kDeg)) {
      h.fail("positioner_deg",
             std::string("has the ") + (i == 0 ? "tilt" : "rotation") + " outside its limits [" +
                 formatNumber(axis.limit.min / kDeg) + ", " + formatNumber(axis.limit.max / kDeg) +
                 "] deg",
             formatNumber(a[i]), "give a home pose within the positioner's limits");
    }
  }
  h.rejectUnknown();
  return home;
}

ToolDescription readTool(Field& top, int version, std::vector<std::string>& notes) {
  ToolDescription tool;
  Field t = top.object("tool", "describe the torch");
  tool.name = t.string("name", "", "tool name");
  tool.number = t.integer("number", 1, 0, 63, "tool number in the controller (0..63)");
  tool.tcp = readPose(t, "tcp", "give the TCP in the flange frame (z along the torch)");
  if (!(tool.tcp.translation().z() > 0.0)) {
    t.fail("tcp/xyz_mm", "puts the TCP on or behind the flange (z along the flange axis)",
           formatNumber(tool.tcp.translation().z()) + " mm",
           "give the TCP in front of the flange, e.g. xyz_mm [0, 0, 400] for a straight 400 mm "
           "torch");
  }
  tool.envelope = readEnvelope(t, version, notes);
  t.rejectUnknown();
  return tool;
}

PositionerDescription readPositioner(Field& top, int version, std::vector<std::string>& notes,
                                     std::string_view origin) {
  Field p = top.object("positioner", "describe the tilt-rotate positioner");
  PositionerDescription pos;
  pos.model = p.string("model", "name the positioner model");
  pos.base = readPose(p, "base", "give the positioner base frame in world");
  Field tilt = p.object("tilt_axis", "give the tilt axis point_mm and direction");
  pos.tiltAxisPoint = tilt.vec3("point_mm", "a point on the tilt axis, positioner base frame");
  pos.tiltAxisDirection = tilt.direction("direction", "tilt axis direction, base frame");
  tilt.rejectUnknown();
  Field rot = p.object("rotation_axis", "give the rotation axis point_mm and direction");
  pos.rotationAxisPoint = rot.vec3("point_mm", "table centre on the rotation axis at tilt 0");
  pos.rotationAxisDirection = rot.direction("direction", "rotation axis direction at tilt 0");
  const double cross = pos.tiltAxisDirection.cross(pos.rotationAxisDirection).norm();
  if (cross < std::sin(1.0 * kDeg)) {
    rot.fail("direction", "must not be parallel to the tilt axis",
             "angle " + formatNumber(std::asin(std::min(1.0, cross)) / kDeg) + " deg",
             "the axes must differ by at least 1 degree");
  }
  rot.rejectUnknown();
  pos.tableToPart = readPose(p, "table_to_part", "give the part frame in the table frame");
  pos.tilt = readAxis(p, "tilt", false);
  pos.rotation = readAxis(p, "rotation", true);
  pos.geometry = readGeometry(p, version, notes);
  pos.fixture = readFixture(p, version, pos.geometry, origin);
  p.rejectUnknown();
  return pos;
}

void readArc(Field& pr, ProcessDescription& proc) {
  Field arc = pr.object("arc", "give the arc conditions");
  proc.arcControl = arc.choice<ArcControl>(
      "control", {{"condition_file", ArcControl::ConditionFile}, {"direct", ArcControl::Direct}},
      "condition_file (ASF#/AEF#) or direct (AC=, AV=)");
  if (proc.arcControl == ArcControl::ConditionFile) {
    proc.arcStartCondition = arc.integer("start_condition", 1, 48, "arc start file number");
    proc.arcEndCondition = arc.integer("end_condition", 1, 12, "arc end file number");
    proc.current = arc.nonNegative("current_a", 0.0, "welding current in A");
    proc.voltage = arc.nonNegative("voltage_v", 0.0, "welding voltage in V");
  } else {
    proc.arcStartCondition = arc.integer("start_condition", 1, 1, 48, "arc start file number");
    proc.arcEndCondition = arc.integer("end_condition", 1, 1, 12, "arc end file number");
    proc.current = arc.positive("current_a", "welding current in A");
    proc.voltage = arc.positive("voltage_v", "welding voltage in V");
  }
  proc.arcStartTime = arc.nonNegative("start_time_s", 0.0, "arc start time in s");
  arc.rejectUnknown();
}

/// Programs give speeds in the controller's unit with 1 decimal (mm/s) or none (per minute): a
/// speed that rounds to 0 there would be written as "V=0.0", which no controller can run.
void checkSpeedsExpressible(Field& pr, const ProcessDescription& proc) {
  double least = 0.05;  // mm/s written with one decimal
  if (proc.speedUnit == SpeedUnit::CentimetresPerMinute) least = 0.5 / 6.0;
  if (proc.speedUnit == SpeedUnit::MillimetresPerMinute) least = 0.5 / 60.0;
  const std::pair<const char*, double> speeds[] = {{"weld_speed_mm_s", proc.weldSpeed},
                                                   {"travel_speed_mm_s", proc.travelSpeed}};
  for (const auto& [key, speed] : speeds) {
    if (speed < least) {
      pr.fail(key, "would be written as 0 in " + std::string(toString(proc.speedUnit)),
              formatNumber(speed), "give at least " + formatNumber(least) + " mm/s");
    }
  }
}

/// An array of arrays of numbers (a bead-model table), shape checked by validateBeadModel.
std::vector<std::vector<double>> readTable(Field& f, std::string_view key, std::string_view hint) {
  const Json& j = f.require(key, hint);
  std::vector<std::vector<double>> rows;
  if (!j.is_array()) f.fail(key, "must be an array of rows of numbers", abbreviateJson(j), hint);
  for (const auto& row : j) {
    if (!row.is_array())
      f.fail(key, "must be an array of rows of numbers", abbreviateJson(j), hint);
    std::vector<double>& out = rows.emplace_back();
    for (const auto& e : row) {
      if (!e.is_number()) f.fail(key, "must hold only numbers", abbreviateJson(row), hint);
      out.push_back(e.get<double>());
    }
  }
  return rows;
}

std::vector<double> readList(Field& f, std::string_view key, std::string_view hint) {
  const Json& j = f.require(key, hint);
  if (!j.is_array()) f.fail(key, "must be an array of numbers", abbreviateJson(j), hint);
  std::vector<double> out;
  for (const auto& e : j) {
    if (!e.is_number()) f.fail(key, "must be an array of numbers", abbreviateJson(j), hint);
    out.push_back(e.get<double>());
  }
  return out;
}

/// The optional bead model (robot/bead_model.hpp): WFS × TS grid, width and height tables.
BeadModel readBeadModel(Field& pr, std::string_view origin) {
  if (!pr.has("bead_model")) return {};
  Field b = pr.object("bead_model", "give the bead width and height over wire feed and speed");
  BeadModel m;
  m.source = b.string("source", "", "where the table comes from");
  m.wireFeeds = readList(b, "wire_feed_m_min", "give the table's wire feed speeds in m/min");
  m.travelSpeeds = readList(b, "travel_speed_mm_s", "give the table's travel speeds in mm/s");
  m.width = readTable(b, "width_mm", "give the bead widths, one row per wire feed");
  m.height = readTable(b, "height_mm", "give the bead heights, one row per wire feed");
  b.rejectUnknown();
  try {
    validateBeadModel(m);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string(origin) + ": " + e.what());
  }
  return m;
}

Json beadModelJson(const BeadModel& m) {
  Json table = Json::object();
  table["source"] = m.source;
  table["wire_feed_m_min"] = m.wireFeeds;
  table["travel_speed_mm_s"] = m.travelSpeeds;
  table["width_mm"] = m.width;
  table["height_mm"] = m.height;
  return table;
}

ProcessDescription readProcess(Field& top, std::string_view origin) {
  Field pr = top.object("process", "describe the welding process");
  ProcessDescription proc;
  proc.weldSpeed = pr.positive("weld_speed_mm_s", "give the welding speed in mm/s");
  proc.travelSpeed = pr.positive("travel_speed_mm_s", "give the arc-off travel speed in mm/s");
  proc.wireFeed = pr.positive("wire_feed_m_min", "give the wire feed speed in m/min");
  proc.wireDiameter = pr.positive("wire_diameter_mm", "give the wire diameter in mm");
  proc.wireDensity = pr.positive("wire_density_g_cm3", "give the wire density in g/cm3");
  proc.depositionEfficiency =
      pr.number("deposition_efficiency", 1.0, "fraction of the wire deposited, in (0, 1]");
  if (!(proc.depositionEfficiency > 0.0 && proc.depositionEfficiency <= 1.0)) {
    pr.fail("deposition_efficiency", "must be in (0, 1]", formatNumber(proc.depositionEfficiency),
            "use e.g. 0.95");
  }
  // at most a day: larger is a unit slip (and would not fit a controller's timer)
  proc.layerDwell = pr.within("layer_dwell_s", 0.0, 0.0, 86400.0, "interlayer dwell in s");
  proc.pathDwell = pr.within("path_dwell_s", 0.0, 0.0, 86400.0, "dwell after each path in s");
  proc.minLayerTime =
      pr.within("min_layer_time_s", kDefaultMinLayerTime, 0.0, 86400.0,
                "the shortest time a layer may take, in s (waits after a faster layer; 0 = off)");
  const double window =
      pr.number("max_torch_angle_deg", 15.0, "the largest torch angle off gravity, in degrees");
  if (!(window >= 0.0 && window <= 45.0)) {
    pr.fail("max_torch_angle_deg", "must be in [0, 45] degrees", formatNumber(window),
            "GMA deposits well within about 15 degrees of the deposition direction, WAAM up to "
            "20-25; use e.g. 15 (0 keeps the torch along gravity)");
  }
  proc.maxTorchAngle = window * kDeg;
  const double deviation = pr.number("max_gravity_deviation_deg", 10.0,
                                     "the largest deposition direction off gravity the planner "
                                     "may use to clear the torch, in degrees");
  if (!(deviation >= 0.0 && deviation <= 45.0)) {
    pr.fail("max_gravity_deviation_deg", "must be in [0, 45] degrees", formatNumber(deviation),
            "a GMA bead tolerates a few degrees off flat; use e.g. 10 (0 keeps the deposition "
            "direction on gravity)");
  }
  proc.maxGravityDeviation = deviation * kDeg;
  proc.speedUnit = pr.choice<SpeedUnit>("speed_unit",
                                        {{"mm/s", SpeedUnit::MillimetresPerSecond},
                                         {"cm/min", SpeedUnit::CentimetresPerMinute},
                                         {"mm/min", SpeedUnit::MillimetresPerMinute}},
                                        "the speed unit set in the controller");
  checkSpeedsExpressible(pr, proc);
  readArc(pr, proc);
  proc.beadModel = readBeadModel(pr, origin);
  pr.rejectUnknown();
  return proc;
}

ExportDescription readExport(Field& top) {
  Field e = top.object("export", "give the export options");
  ExportDescription ex;
  ex.coordinated = e.boolean("coordinated", "true: robot and positioner move together");
  ex.positionType = e.choice<PositionType>(
      "position_type",
      {{"pulse", PositionType::Pulse}, {"base", PositionType::Base}, {"user", PositionType::User}},
      "how robot targets are written");
  ex.maxLinesPerJob = e.integer("max_lines_per_job", 20, 1000000, "lines per job before split");
  ex.lineEnding =
      e.choice<LineEnding>("line_ending", {{"crlf", LineEnding::Crlf}, {"lf", LineEnding::Lf}},
                           "crlf for Yaskawa controllers");
  ex.maxNameLength = e.integer("max_name_length", 8, 32, "8 on NX100, 32 on DX100 and later");
  ex.jobName = e.string("job_name", "base name of the jobs");
  if (ex.jobName.empty() || static_cast<int>(ex.jobName.size()) > ex.maxNameLength) {
    e.fail("job_name", "must have 1 to max_name_length characters",
           abbreviateJson(Json(ex.jobName)), "use a shorter name");
  }
  for (char c : ex.jobName) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) {
      e.fail("job_name", "may only contain letters, digits, '_' and '-'",
             abbreviateJson(Json(ex.jobName)), "rename the job");
    }
  }
  ex.userFrame = e.integer("user_frame", 1, 1, 63, "user frame number (1..63)");
  e.rejectUnknown();
  return ex;
}

/// "vendor": optional in every version; without it the vendor is Unknown and a note says so.
RobotVendor readVendor(Field& top, std::vector<std::string>& notes) {
  if (!top.has("vendor")) {
    notes.push_back(
        "cell names no vendor: programs are not checked against the controller family; add "
        "\"vendor\": \"yaskawa\", \"kuka\", \"abb\" or \"fanuc\"");
    return RobotVendor::Unknown;
  }
  return top.choice<RobotVendor>("vendor",
                                 {{"yaskawa", RobotVendor::Yaskawa},
                                  {"kuka", RobotVendor::Kuka},
                                  {"abb", RobotVendor::Abb},
                                  {"fanuc", RobotVendor::Fanuc}},
                                 "the robot controller's maker (decides the program languages)");
}

// ---- controller (vendor-specific program settings) -------------------------------------------

KrlController readKrlController(Field& c) {
  Field k = c.object("krl", "give the KUKA KRL settings");
  KrlController krl;
  krl.arcOnOutput = k.integer("arc_on_output", 1, 4096, "the $OUT[n] that switches the arc on");
  krl.arcEstablishedInput =
      k.integer("arc_established_input", 0, 0, 4096, "$IN[m] set once the arc burns; 0 = none");
  krl.wireFeedAnalogOutput =
      k.integer("wire_feed_analog_output", 0, 0, 32, "$ANOUT[n] for the wire feed; 0 = none");
  if (krl.wireFeedAnalogOutput > 0) {
    krl.wireFeedFullScale =
        k.positive("wire_feed_full_scale_m_min", "give the wire feed (m/min) at $ANOUT = 1.0");
  }
  krl.approximationDistance =
      k.number("approximation_mm", 1.0, "C_DIS approximation distance in mm ($APO.CDIS)");
  if (!(krl.approximationDistance > 0.0)) {
    k.fail("approximation_mm", "must be positive", formatNumber(krl.approximationDistance),
           "use e.g. 1.0");
  }
  krl.baseNumber = k.integer("base_number", 1, 1, 32, "BASE_DATA[n] of the table frame");
  krl.maxLinesPerFile =
      k.integer("max_lines_per_file", 0, 0, 1000000, "lines per .src; 0 = max_lines_per_job");
  if (krl.maxLinesPerFile > 0 && krl.maxLinesPerFile < 20) {
    k.fail("max_lines_per_file", "must be 0 or at least 20", std::to_string(krl.maxLinesPerFile),
           "use e.g. 5000");
  }
  k.rejectUnknown();
  return krl;
}

/// A RAPID identifier: a letter, then letters, digits or '_', at most 32 characters.
std::string readRapidName(Field& f, std::string_view key, bool required, std::string_view hint) {
  const std::string name = required ? f.string(key, hint) : f.string(key, "", hint);
  if (!required && name.empty()) return name;
  bool valid =
      !name.empty() && name.size() <= 32 && std::isalpha(static_cast<unsigned char>(name[0]));
  for (char ch : name) valid = valid && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
  if (!valid) {
    f.fail(key, "must be a RAPID name (a letter, then letters, digits or '_', at most 32)",
           abbreviateJson(Json(name)), hint);
  }
  return name;
}

RapidController readRapidController(Field& c, bool coordinated) {
  Field r = c.object("rapid", "give the ABB RAPID settings");
  RapidController rapid;
  rapid.arcSignal =
      readRapidName(r, "arc_signal", true, "the digital output that switches the arc");
  rapid.arcEstablishedSignal =
      readRapidName(r, "arc_established_signal", false, "digital input set once the arc burns");
  rapid.wireFeedSignal =
      readRapidName(r, "wire_feed_signal", false, "analog output of the wire feed in m/min");
  if (coordinated || r.has("mech_unit")) {
    rapid.mechUnit = readRapidName(r, "mech_unit", true,
                                   "the positioner's mechanical unit, e.g. \"STN1\" (coordinated "
                                   "export needs it)");
  }
  rapid.toolMass = r.positive("tool_mass_kg", "give the torch mass in kg (tooldata load)");
  rapid.toolCog = r.vec3("tool_cog_mm", "give the torch's centre of gravity in the flange frame");
  rapid.maxLinesPerModule =
      r.integer("max_lines_per_module", 0, 0, 1000000, "lines per module; 0 = max_lines_per_job");
  if (rapid.maxLinesPerModule > 0 && rapid.maxLinesPerModule < 20) {
    r.fail("max_lines_per_module", "must be 0 or at least 20",
           std::to_string(rapid.maxLinesPerModule), "use e.g. 5000");
  }
  r.rejectUnknown();
  return rapid;
}

LsControllerSettings readLsController(Field& c) {
  Field f = c.object("ls", "give the Fanuc ArcTool settings");
  LsControllerSettings ls;
  ls.weldEquipment = f.integer("weld_equipment", 1, 2, "the ArcTool weld equipment number");
  ls.arcStartSchedule = f.integer("arc_start_schedule", 1, 99, "the weld schedule of Arc Start[n]");
  ls.arcEndSchedule = f.integer("arc_end_schedule", 1, 99, "the schedule of Arc End[n]");
  ls.maxLinesPerProgram = f.integer("max_lines_per_program", 20, 1000000,
                                    "/MN lines per program before the program is split");
  f.rejectUnknown();
  return ls;
}

JbiControllerSettings readJbiController(Field& c) {
  Field f = c.object("jbi", "give the Yaskawa settings");
  JbiControllerSettings jbi;
  jbi.arcWaitInput = f.integer("arc_wait_input", 0, 0, 2048,
                               "the input IN#(n) that says the arc is established, 0 = none");
  f.rejectUnknown();
  return jbi;
}

ControllerDescription readController(Field& top, std::string_view origin, bool coordinated) {
  ControllerDescription controller;
  controller.source = std::string(origin);
  if (!top.has("controller")) return controller;
  Field c = top.object("controller", "give the vendor-specific program settings");
  if (c.has("krl")) controller.krl = readKrlController(c);
  if (c.has("rapid")) controller.rapid = readRapidController(c, coordinated);
  if (c.has("ls")) controller.ls = readLsController(c);
  if (c.has("jbi")) controller.jbi = readJbiController(c);
  c.rejectUnknown();
  return controller;
}

Json controllerJson(const ControllerDescription& controller) {
  Json j = Json::object();
  if (const auto& k = controller.krl) {
    j["krl"] = Json{{"arc_on_output", k->arcOnOutput},
                    {"arc_established_input", k->arcEstablishedInput},
                    {"wire_feed_analog_output", k->wireFeedAnalogOutput},
                    {"approximation_mm", clean(k->approximationDistance)},
                    {"base_number", k->baseNumber},
                    {"max_lines_per_file", k->maxLinesPerFile}};
    if (k->wireFeedAnalogOutput > 0)
      j["krl"]["wire_feed_full_scale_m_min"] = clean(k->wireFeedFullScale);
  }
  if (const auto& r = controller.rapid) {
    j["rapid"] = Json{{"arc_signal", r->arcSignal},
                      {"arc_established_signal", r->arcEstablishedSignal},
                      {"wire_feed_signal", r->wireFeedSignal},
                      {"tool_mass_kg", clean(r->toolMass)},
                      {"tool_cog_mm", vecJson(r->toolCog)},
                      {"max_lines_per_module", r->maxLinesPerModule}};
    if (!r->mechUnit.empty()) j["rapid"]["mech_unit"] = r->mechUnit;
  }
  if (controller.ls) {
    const LsControllerSettings& ls = *controller.ls;
    j["ls"] = Json{{"weld_equipment", ls.weldEquipment},
                   {"arc_start_schedule", ls.arcStartSchedule},
                   {"arc_end_schedule", ls.arcEndSchedule},
                   {"max_lines_per_program", ls.maxLinesPerProgram}};
  }
  if (controller.jbi) j["jbi"] = Json{{"arc_wait_input", controller.jbi->arcWaitInput}};
  return j;
}
// ---- end controller --------------------------------------------------------------------------

Cell readCellDocument(const Json& root, std::string_view origin) {
  if (!root.is_object()) {
    throw InvalidInput(std::string(origin) + ": the cell description must be a JSON object: " +
                       std::string(root.type_name()) + "; see resources/cells/ for examples");
  }
  Field top(root, "", origin);
  Cell cell;
  if (top.has("format") &&
      top.string("format", "must be \"curvedslicer-cell\"") != "curvedslicer-cell") {
    top.fail("format", "must be \"curvedslicer-cell\"", abbreviateJson(root["format"]),
             "this is not a cell description");
  }
  const int version = top.integer("version", 1, 1, kCellFormatVersion,
                                  "versions 1 to 3 are known; write 3 (see "
                                  "resources/schema/cell.schema.json)");
  cell.name = top.string("name", "give the cell a name");
  cell.vendor = readVendor(top, cell.notes);
  cell.description = top.string("description", "", "free text");
  cell.gravity = top.direction("gravity", "give gravity as a direction in world, e.g. [0, 0, -1]");
  cell.robot = readRobot(top, origin, cell.vendor, version, cell.notes);
  cell.tool = readTool(top, version, cell.notes);
  cell.positioner = readPositioner(top, version, cell.notes, origin);
  cell.process = readProcess(top, origin);
  cell.exportOptions = readExport(top);
  cell.controller = readController(top, origin, cell.exportOptions.coordinated);
  cell.home = readHome(top, version, cell, cell.notes);
  if (cell.exportOptions.positionType == PositionType::Pulse &&
      cell.robot.pulsesPerDegree.empty()) {
    top.fail("robot/pulses_per_degree", "is missing but export position_type is \"pulse\"",
             "(absent)", "add the six pulses-per-degree values or use position_type \"base\"");
  }
  top.rejectUnknown();
  return cell;
}

}  // namespace

Pose makePose(const Vec3& translation, const Vec3& rpy) {
  Pose pose = Pose::Identity();
  pose.linear() =
      (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
       Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
          .toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

Vec3 rollPitchYaw(const Mat3& r) {
  const double pitch = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  double roll, yaw;
  if (std::hypot(r(0, 0), r(1, 0)) < 1e-12) {  // gimbal lock: put everything in yaw
    roll = 0.0;
    yaw = std::atan2(-r(0, 1), r(1, 1));
  } else {
    roll = std::atan2(r(2, 1), r(2, 2));
    yaw = std::atan2(r(1, 0), r(0, 0));
  }
  return Vec3(roll, pitch, yaw);
}

std::string_view toString(RobotVendor vendor) {
  switch (vendor) {
    case RobotVendor::Yaskawa:
      return "yaskawa";
    case RobotVendor::Kuka:
      return "kuka";
    case RobotVendor::Abb:
      return "abb";
    case RobotVendor::Fanuc:
      return "fanuc";
    case RobotVendor::Unknown:
      break;
  }
  return "unknown";
}

double interferenceExcess(const RobotDescription& robot, const JointVector& joints) {
  double worst = -std::numeric_limits<double>::infinity();
  for (const JointInequality& limit : robot.interference) {
    double sum = 0.0;
    for (int j = 0; j < 6; ++j) sum += limit.coefficients[j] * joints[j];
    worst = std::max(worst, sum - limit.max);
  }
  return worst;
}

const JointInequality* violatedInterference(const RobotDescription& robot,
                                            const JointVector& joints, double tolerance) {
  for (const JointInequality& limit : robot.interference) {
    double sum = 0.0;
    for (int j = 0; j < 6; ++j) sum += limit.coefficients[j] * joints[j];
    if (sum - limit.max > tolerance) return &limit;
  }
  return nullptr;
}

Pose defaultControllerFrame(RobotVendor vendor, const RobotKinematics& kinematics) {
  Pose frame = Pose::Identity();
  if (vendor == RobotVendor::Yaskawa || vendor == RobotVendor::Fanuc) {
    frame.translation() = Vec3(0.0, 0.0, kinematics.c1);
  }
  return frame;
}

RobotVendor vendorOfFormat(std::string_view format) {
  if (format == "jbi") return RobotVendor::Yaskawa;
  if (format == "krl") return RobotVendor::Kuka;
  if (format == "rapid") return RobotVendor::Abb;
  if (format == "ls") return RobotVendor::Fanuc;
  return RobotVendor::Unknown;
}

void checkCellVendor(const Cell& cell, std::string_view format, bool allowForeign) {
  const RobotVendor language = vendorOfFormat(format);
  if (allowForeign || language == RobotVendor::Unknown || cell.vendor == RobotVendor::Unknown ||
      cell.vendor == language) {
    return;
  }
  throw InvalidInput("the cell is for a " + std::string(toString(cell.vendor)) +
                     " controller but the format " + std::string(format) + " is for " +
                     std::string(toString(language)) + ": cell '" + cell.name +
                     "'; choose a cell of that vendor (resources/cells/), the format of yours, "
                     "or --allow-foreign-cell to write it anyway");
}

std::string_view toString(SpeedUnit unit) {
  switch (unit) {
    case SpeedUnit::MillimetresPerSecond:
      return "mm/s";
    case SpeedUnit::CentimetresPerMinute:
      return "cm/min";
    case SpeedUnit::MillimetresPerMinute:
      return "mm/min";
  }
  return "mm/s";
}
std::string_view toString(ArcControl control) {
  return control == ArcControl::Direct ? "direct" : "condition_file";
}
std::string_view toString(PositionType type) {
  switch (type) {
    case PositionType::Pulse:
      return "pulse";
    case PositionType::Base:
      return "base";
    case PositionType::User:
      return "user";
  }
  return "base";
}
std::string_view toString(LineEnding ending) {
  return ending == LineEnding::Lf ? "lf" : "crlf";
}

Cell parseCell(std::string_view text, std::string_view origin) {
  const Json root = parseBoundedJson(text, std::string(origin) + ": not valid JSON",
                                     "fix the syntax of the cell file");
  try {
    return readCellDocument(root, origin);
  } catch (const Json::exception& e) {
    // The field checks should leave the library nothing to object to; name the file if it does.
    throw InvalidInput(std::string(origin) + ": unexpected content (" +
                       std::string(e.what()).substr(0, 200) +
                       "); check it against resources/schema/cell.schema.json");
  }
}

Cell readCell(const std::filesystem::path& path) {
  // a regular file of at most 16 MiB: a FIFO, a device or a folder is refused unread
  return parseCell(readInputFile(path, "cell file", kMaxCellFileBytes), path.filename().string());
}

/// The robot section of writeCellJson.
Json robotJson(const RobotDescription& r) {
  Json joints = Json::array();
  for (int i = 0; i < 6; ++i) {
    Json jj = limitJson(r.joints[i]);
    jj["name"] = kJointNames[i];
    jj["sign"] = static_cast<int>(r.jointSigns[i]);
    jj["offset_deg"] = clean(r.jointOffsets[i] / kDeg);
    joints.push_back(jj);
  }
  const RobotKinematics& k = r.kinematics;
  Json j{{"model", r.model},
         {"base", poseJson(r.base)},
         {"kinematics_mm",
          {{"a1", k.a1},
           {"a2", k.a2},
           {"b", k.b},
           {"c1", k.c1},
           {"c2", k.c2},
           {"c3", k.c3},
           {"c4", k.c4}}},
         {"joints", joints}};
  if (!r.pulsesPerDegree.empty()) j["pulses_per_degree"] = r.pulsesPerDegree;
  if (r.j3RelativeToHorizontal) j["j3_relative_to_horizontal"] = true;
  j["controller_frame"] = poseJson(r.controllerFrame);
  Json interference = Json::array();
  for (const JointInequality& limit : r.interference) {
    Json c = Json::array();
    for (double v : limit.coefficients) c.push_back(clean(v));
    interference.push_back(
        Json{{"name", limit.name}, {"coefficients", c}, {"max_deg", clean(limit.max / kDeg)}});
  }
  j["interference"] = interference;
  if (r.links.known()) {
    j["link_capsules_mm"] = Json{{"column", clean(r.links.column)},
                                 {"upper_arm", clean(r.links.upperArm)},
                                 {"upper_arm_offset", clean(r.links.upperArmOffset)},
                                 {"elbow", clean(r.links.elbow)},
                                 {"forearm", clean(r.links.forearm)},
                                 {"wrist", clean(r.links.wrist)}};
  }
  return j;
}

std::string writeCellJson(const Cell& cell) {
  Json j;
  j["format"] = "curvedslicer-cell";
  // A cell whose arm and positioner body are not known (read from a version-2 file, or built in
  // code without them) is written as version 2, which reads back the same; otherwise version 3,
  // whose reader names whichever of the two is missing.
  const bool wholeCell = cell.robot.links.known() || cell.positioner.geometry.bodyRadius > 0.0;
  j["version"] = wholeCell ? kCellFormatVersion : 2;
  j["name"] = cell.name;
  if (cell.vendor != RobotVendor::Unknown) j["vendor"] = std::string(toString(cell.vendor));
  j["description"] = cell.description;
  j["gravity"] = vecJson(cell.gravity);
  j["robot"] = robotJson(cell.robot);
  const TorchEnvelope& env = cell.tool.envelope;
  j["tool"] = Json{{"name", cell.tool.name},
                   {"number", cell.tool.number},
                   {"tcp", poseJson(cell.tool.tcp)},
                   {"envelope",
                    {{"stickout_mm", clean(env.stickout)},
                     {"radius_mm", clean(env.radius)},
                     {"top_radius_mm", clean(env.topRadius)},
                     {"length_mm", clean(env.length)}}}};
  const PositionerDescription& p = cell.positioner;
  j["positioner"] =
      Json{{"model", p.model},
           {"base", poseJson(p.base)},
           {"tilt_axis",
            {{"point_mm", vecJson(p.tiltAxisPoint)}, {"direction", vecJson(p.tiltAxisDirection)}}},
           {"rotation_axis",
            {{"point_mm", vecJson(p.rotationAxisPoint)},
             {"direction", vecJson(p.rotationAxisDirection)}}},
           {"table_to_part", poseJson(p.tableToPart)},
           {"tilt", axisJson(p.tilt)},
           {"rotation", axisJson(p.rotation)},
           {"geometry",
            {{"table_radius_mm", clean(p.geometry.tableRadius)},
             {"table_thickness_mm", clean(p.geometry.tableThickness)},
             {"max_part_radius_mm", clean(p.geometry.maxPartRadius)},
             {"max_part_height_mm", clean(p.geometry.maxPartHeight)}}}};
  if (p.geometry.bodyRadius > 0.0) {
    j["positioner"]["geometry"]["body_radius_mm"] = clean(p.geometry.bodyRadius);
  }
  const FixtureGeometry& f = p.fixture;
  if (f.hasRiser() || f.hasSubstrate() || f.riserDiameter > 0.0 || f.substrateSize > 0.0) {
    j["positioner"]["fixture"] = Json{{"riser_height_mm", clean(f.riserHeight)},
                                      {"riser_diameter_mm", clean(f.riserDiameter)},
                                      {"substrate_thickness_mm", clean(f.substrateThickness)},
                                      {"substrate_size_mm", clean(f.substrateSize)}};
  }
  const ProcessDescription& pr = cell.process;
  Json arc{{"control", std::string(toString(pr.arcControl))},
           {"start_condition", pr.arcStartCondition},
           {"end_condition", pr.arcEndCondition},
           {"current_a", pr.current},
           {"voltage_v", pr.voltage},
           {"start_time_s", pr.arcStartTime}};
  j["process"] = Json{{"weld_speed_mm_s", pr.weldSpeed},
                      {"travel_speed_mm_s", pr.travelSpeed},
                      {"wire_feed_m_min", pr.wireFeed},
                      {"wire_diameter_mm", pr.wireDiameter},
                      {"wire_density_g_cm3", pr.wireDensity},
                      {"deposition_efficiency", pr.depositionEfficiency},
                      {"layer_dwell_s", pr.layerDwell},
                      {"path_dwell_s", pr.pathDwell},
                      {"min_layer_time_s", pr.minLayerTime},
                      {"max_torch_angle_deg", clean(pr.maxTorchAngle / kDeg)},
                      {"max_gravity_deviation_deg", clean(pr.maxGravityDeviation / kDeg)},
                      {"speed_unit", std::string(toString(pr.speedUnit))},
                      {"arc", arc}};
  if (!pr.beadModel.empty()) j["process"]["bead_model"] = beadModelJson(pr.beadModel);
  const ExportDescription& e = cell.exportOptions;
  j["export"] = Json{{"coordinated", e.coordinated},
                     {"position_type", std::string(toString(e.positionType))},
                     {"max_lines_per_job", e.maxLinesPerJob},
                     {"line_ending", std::string(toString(e.lineEnding))},
                     {"job_name", e.jobName},
                     {"max_name_length", e.maxNameLength},
                     {"user_frame", e.userFrame}};
  if (Json controller = controllerJson(cell.controller); !controller.empty()) {
    j["controller"] = controller;
  }
  Json homeJoints = Json::array();
  for (double q : cell.home.robot) homeJoints.push_back(clean(q / kDeg));
  j["home"] = Json{{"robot_joints_deg", homeJoints},
                   {"positioner_deg", {clean(cell.home.a1 / kDeg), clean(cell.home.a2 / kDeg)}}};
  return j.dump(2) + "\n";
}

void validateFixture(const FixtureGeometry& fixture, const PositionerGeometry& geometry,
                     std::string_view origin) {
  const auto fail = [&](std::string_view field, std::string_view problem, double value,
                        std::string_view hint) {
    throw InvalidInput(std::string(origin) + std::string(field) + " " + std::string(problem) +
                       ": " + formatNumber(value) + " mm; " + std::string(hint));
  };
  const std::pair<const char*, double> sizes[] = {
      {"riser_height_mm", fixture.riserHeight},
      {"riser_diameter_mm", fixture.riserDiameter},
      {"substrate_thickness_mm", fixture.substrateThickness},
      {"substrate_size_mm", fixture.substrateSize}};
  for (const auto& [field, value] : sizes) {
    if (!std::isfinite(value) || value < 0.0) {
      fail(field, "must be a finite size, not negative", value, "give 0 for none or a size in mm");
    }
  }
  if (fixture.hasRiser() && !(fixture.riserDiameter > 0.0)) {
    fail("riser_diameter_mm", "must be positive with a riser", fixture.riserDiameter,
         "give the riser's diameter, or riser_height_mm 0 for no riser");
  }
  if (fixture.hasSubstrate() && !(fixture.substrateSize > 0.0)) {
    fail("substrate_size_mm", "must be positive with a substrate plate", fixture.substrateSize,
         "give the plate's side, or substrate_thickness_mm 0 for no plate");
  }
  if (fixture.riserDiameter > 2.0 * geometry.tableRadius) {
    fail("riser_diameter_mm",
         "is wider than the table (diameter " + formatNumber(2.0 * geometry.tableRadius) + " mm)",
         fixture.riserDiameter, "give the riser's diameter as measured");
  }
  if (0.5 * std::sqrt(2.0) * fixture.substrateSize > geometry.maxPartRadius) {
    fail("substrate_size_mm",
         "puts the plate's corners outside the working volume (radius " +
             formatNumber(geometry.maxPartRadius) + " mm)",
         fixture.substrateSize, "give the plate's side as measured, or a larger working volume");
  }
  if (fixture.top() >= geometry.maxPartHeight) {
    fail("riser_height_mm",
         "and the plate leave no room in the working volume (height " +
             formatNumber(geometry.maxPartHeight) + " mm, fixture top " +
             formatNumber(fixture.top()) + " mm)",
         fixture.riserHeight, "give the fixture as measured, or a taller working volume");
  }
}

void validateCell(const Cell& cell) {
  parseCell(writeCellJson(cell), "cell");
}

Cell defaultCell() {
  // Numbers and their sources: resources/cells/README.md. Keep equal to
  // resources/cells/motoman_hp20d_tilt_rotate.json (a test checks it).
  Cell cell;
  cell.name = "Motoman HP20D with two-axis tilt-rotate positioner";
  cell.vendor = RobotVendor::Yaskawa;
  cell.description =
      "The paper's cell (section 4.1). Robot dimensions from the HP20D datasheet; positioner "
      "after the D500B-class numbers in resources/cells/README.md; placement is an example.";
  cell.gravity = -Vec3::UnitZ();
  RobotDescription& r = cell.robot;
  r.model = "Yaskawa Motoman HP20D";
  r.base = Pose::Identity();
  r.kinematics = RobotKinematics{150.0, 140.0, 0.0, 505.0, 760.0, 795.0, 100.0};
  // Yaskawa's robot coordinates: on the S axis at the height of the L axis.
  r.controllerFrame = defaultControllerFrame(RobotVendor::Yaskawa, r.kinematics);
  // U is limited relative to the L arm (-86/+160 deg, the GP25's range with the same arm
  // lengths): the datasheet's -165/+255 deg is the forearm's angle to the ground, and that range
  // relative to L would fold the forearm onto the upper arm (resources/cells/README.md).
  const double limits[6][2] = {{-180, 180}, {-110, 155}, {-86, 160},
                               {-200, 200}, {-125, 125}, {-360, 360}};
  const double speeds[6] = {197, 197, 210, 410, 410, 610};
  for (int i = 0; i < 6; ++i) {
    r.joints[i] = JointLimit{limits[i][0] * kDeg, limits[i][1] * kDeg, speeds[i] * kDeg};
  }
  // Controller angles: U positive = forearm up, B positive = wrist up, which turn about -y in the
  // model (see docs/METHODS.md); R and T positive about the forearm / flange axis. T's offset of
  // 180° turns the model's flange (x down at the zero pose) into Yaskawa's flange frame (x up),
  // in which the controller's tool files and the Rx, Ry, Rz of BASE positions are given.
  r.jointSigns = {1, 1, -1, -1, -1, -1};
  r.jointOffsets = {0, 0, 0, 0, 0, 180 * kDeg};
  // Capsules holding every vertex of the GP25's published collision meshes (no HP20D
  // description is published; resources/cells/README.md).
  r.links = ArmEnvelope{364.0, 123.0, -138.6, 381.0, 139.0, 86.0};
  cell.tool.name = "straight WAAM torch, TCP 400 mm along the flange axis";
  cell.tool.number = 1;
  cell.tool.tcp = makePose(Vec3(0, 0, 400), Vec3::Zero());
  cell.tool.envelope = TorchEnvelope{15.0, 12.5, 25.0, 385.0};
  PositionerDescription& p = cell.positioner;
  p.model = "two-axis tilt-rotate positioner (Yaskawa D500B class)";
  p.base = makePose(Vec3(1100, 0, 0), Vec3::Zero());
  p.tiltAxisPoint = Vec3(0, 0, 380);
  p.tiltAxisDirection = Vec3::UnitX();
  p.rotationAxisPoint = Vec3(0, 0, 530);
  p.rotationAxisDirection = Vec3::UnitZ();
  p.tableToPart = Pose::Identity();
  p.tilt = PositionerAxis{JointLimit{-95 * kDeg, 95 * kDeg, 120 * kDeg}, false, 1994.3, 1};
  p.rotation = PositionerAxis{JointLimit{-360 * kDeg, 360 * kDeg, 180 * kDeg}, true, 1376.7, 1};
  p.geometry = PositionerGeometry{300.0, 30.0, 350.0, 500.0, 150.0};
  ProcessDescription& pr = cell.process;
  pr.weldSpeed = 8.0;
  pr.travelSpeed = 50.0;
  pr.wireFeed = 5.0;
  pr.wireDiameter = 1.2;
  pr.wireDensity = 7.85;
  pr.depositionEfficiency = 1.0;
  pr.layerDwell = 60.0;
  pr.pathDwell = 0.0;
  pr.minLayerTime = kDefaultMinLayerTime;
  pr.speedUnit = SpeedUnit::MillimetresPerSecond;
  pr.arcControl = ArcControl::ConditionFile;
  pr.arcStartCondition = 1;
  pr.arcEndCondition = 1;
  pr.current = 0.0;
  pr.voltage = 0.0;
  pr.arcStartTime = 0.0;
  // Example bead model (not measured; see resources/cells/README.md).
  BeadModel& bead = pr.beadModel;
  bead.source =
      "Example table, not measured: computed from mass conservation for 1.2 mm steel wire (bead "
      "section 2/3 x width x height = 0.9 x wire area x WFS / TS) with an assumed width/height "
      "ratio 1.6 + 0.25 x WFS[m/min]; shaped like the WFS x TS grids of published GMA-AM bead "
      "studies (resources/cells/README.md). Replace with your own calibration.";
  bead.wireFeeds = {2.0, 3.5, 5.0, 6.5, 8.0};
  bead.travelSpeeds = {4.0, 8.0, 12.0, 16.0, 20.0, 24.0};
  bead.width = {{5.17, 3.66, 2.98, 2.58, 2.31, 2.11},
                {7.42, 5.25, 4.29, 3.71, 3.32, 3.03},
                {9.52, 6.73, 5.5, 4.76, 4.26, 3.89},
                {11.55, 8.17, 6.67, 5.77, 5.16, 4.71},
                {13.54, 9.57, 7.81, 6.77, 6.05, 5.53}};
  bead.height = {{2.46, 1.74, 1.42, 1.23, 1.1, 1.0},
                 {3.0, 2.12, 1.73, 1.5, 1.34, 1.22},
                 {3.34, 2.36, 1.93, 1.67, 1.49, 1.36},
                 {3.58, 2.53, 2.07, 1.79, 1.6, 1.46},
                 {3.76, 2.66, 2.17, 1.88, 1.68, 1.53}};
  ExportDescription& e = cell.exportOptions;
  e.coordinated = true;
  e.positionType = PositionType::Base;
  e.maxLinesPerJob = 2000;
  e.lineEnding = LineEnding::Crlf;
  e.jobName = "WAAM";
  e.maxNameLength = 8;
  e.userFrame = 1;
  // Controller settings for exporting KRL and RAPID programs with this cell (examples; sources
  // and how to adapt them in resources/cells/README.md).
  KrlController krl;
  krl.arcOnOutput = 1;
  krl.arcEstablishedInput = 1;
  krl.approximationDistance = 1.0;
  krl.baseNumber = 1;
  cell.controller.krl = krl;
  RapidController rapid;
  rapid.arcSignal = "doArcOn";
  rapid.arcEstablishedSignal = "diArcEst";
  rapid.wireFeedSignal = "aoWireFeed";
  rapid.mechUnit = "STN1";
  rapid.toolMass = 2.0;
  rapid.toolCog = Vec3(0, 0, 150);
  cell.controller.rapid = rapid;
  // Fanuc ArcTool schedule 1 on weld equipment 1, 2000 lines per program; no arc wait input.
  cell.controller.ls = LsControllerSettings{1, 1, 1, 2000};
  cell.controller.jbi = JbiControllerSettings{0};
  // Torch vertical, TCP at (648.7, 0, 995.1) mm in world (490.1 mm above the robot coordinates'
  // origin at the L axis): 100 mm outside the working volume's radius and 465 mm above the table
  // top (checked by a test with the robot's FK).
  cell.home.robot = {0.0, -20 * kDeg, -10 * kDeg, 0.0, -100 * kDeg, 0.0};
  cell.home.a1 = 0.0;
  cell.home.a2 = 0.0;
  return cell;
}

}  // namespace curvedslicer
