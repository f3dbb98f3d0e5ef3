// The `curvedslicer cell check CELL.json` command: reads a cell description (robot/cell.hpp) and
// prints what a controller and a planner take from it — the frames (world, robot base, the
// controller's robot frame, flange and TCP), the arm's reach, the joint and positioner limits,
// the interference limits and where the numbers come from (the cell's description and sources
// texts, the reader's notes). It exits 2 when the cell cannot be read or when joints 2 and 3 can
// fold the forearm onto the upper arm with no interference limit against it (findFoldedPose).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command_errors.hpp"
#include "commands.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "layers_command.hpp"  // ExitCode
#include "terminal_progress.hpp"

namespace curvedslicer::cli {

namespace {

constexpr double kToDeg = 180.0 / 3.14159265358979323846;

struct CellCheckArguments {
  std::string cell;
};

/// `v` rounded to `decimals`, without a negative zero ("-0.0" for -1e-13).
double printable(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

std::string xyzRpy(const Pose& pose) {
  const Vec3 t = pose.translation();
  const Vec3 r = rollPitchYaw(pose.rotation()) * kToDeg;
  char buf[160];
  std::snprintf(buf, sizeof buf, "xyz %.1f, %.1f, %.1f mm, rpy %.2f, %.2f, %.2f deg",
                printable(t.x(), 1), printable(t.y(), 1), printable(t.z(), 1), printable(r.x(), 2),
                printable(r.y(), 2), printable(r.z(), 2));
  return buf;
}

std::string vec(const Vec3& v, const char* format = "%.3f") {
  std::string out = "(";
  for (int i = 0; i < 3; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, format, v[i] + 0.0);
    out += (i ? ", " : "") + std::string(buf);
  }
  return out + ")";
}

std::string joints(const JointVector& q) {
  std::string out;
  for (int j = 0; j < 6; ++j) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.1f", j ? ", " : "", q[j] * kToDeg + 0.0);
    out += buf;
  }
  return out + " deg";
}

/// The free texts of the file that say where its numbers come from: "description", "sources"
/// and "comment" of the top level and of the robot, tool and positioner objects.
void printSources(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (!j.is_object()) return;
  std::printf("sources:\n");
  for (const char* section : {"", "robot", "tool", "positioner"}) {
    const nlohmann::json o = *section ? j.value(section, nlohmann::json::object()) : j;
    if (!o.is_object()) continue;
    for (const char* key : {"description", "sources", "comment"}) {
      if (o.contains(key) && o[key].is_string()) {
        std::printf("  %s%s%s: %s\n", section, *section ? "/" : "", key,
                    o[key].get<std::string>().c_str());
      }
    }
  }
  std::printf("  every number of the bundled cells: resources/cells/README.md\n");
}

void printRobot(const Cell& cell) {
  const RobotDescription& r = cell.robot;
  const RobotKinematics& k = r.kinematics;
  std::printf("robot: %s (vendor %s)\n", r.model.c_str(),
              std::string(toString(cell.vendor)).c_str());
  std::printf("  base in world: %s\n", xyzRpy(r.base).c_str());
  const Pose convention = defaultControllerFrame(cell.vendor, k);
  std::printf(
      "  controller's robot frame in the base: %s (%s)\n", xyzRpy(r.controllerFrame).c_str(),
      r.controllerFrame.isApprox(convention, 1e-9) ? "the vendor's convention"
                                                   : "differs from the vendor's convention");
  std::printf("  kinematics: a1 %.1f, a2 %.1f, b %.1f, c1 %.1f, c2 %.1f, c3 %.1f, c4 %.1f mm\n",
              k.a1, k.a2, k.b, k.c1, k.c2, k.c3, k.c4);
  std::printf(
      "  reach: wrist centre up to %.1f mm from joint 1's axis (a1 + c2 + sqrt(c3^2 + a2^2))\n",
      k.a1 + k.c2 + std::hypot(k.c3, k.a2));
  const Pose zero = computeFlangePose(r, JointVector{});
  std::printf("  flange at all joints 0: %s in the controller's robot frame; z %s, x %s\n",
              xyzRpy(r.controllerFrame.inverse() * zero).c_str(),
              vec(zero.linear().col(2), "%.0f").c_str(), vec(zero.linear().col(0), "%.0f").c_str());
  for (int j = 0; j < 6; ++j) {
    const JointLimit& l = r.joints[j];
    std::printf("  joint %d: [%.1f, %.1f] deg, %.1f deg/s, sign %+.0f, offset %.1f deg\n", j + 1,
                l.min * kToDeg, l.max * kToDeg, l.maxSpeed * kToDeg, r.jointSigns[j],
                r.jointOffsets[j] * kToDeg + 0.0);
  }
  if (r.j3RelativeToHorizontal) std::printf("  joint 3 measured from the horizontal (Fanuc)\n");
  if (r.interference.empty()) std::printf("  interference limits: none\n");
  for (const JointInequality& limit : r.interference) {
    // e.g. "-J2 - J3", "J2 + 0.5 J3"
    std::string sum;
    for (int j = 0; j < 6; ++j) {
      const double c = limit.coefficients[j];
      if (c == 0.0) continue;
      const char* sign = c < 0.0 ? (sum.empty() ? "-" : " - ") : (sum.empty() ? "" : " + ");
      char buf[48];
      if (std::abs(c) == 1.0) {
        std::snprintf(buf, sizeof buf, "%sJ%d", sign, j + 1);
      } else {
        std::snprintf(buf, sizeof buf, "%s%g J%d", sign, std::abs(c), j + 1);
      }
      sum += buf;
    }
    std::printf("  interference limit %s: %s <= %.1f deg\n", limit.name.c_str(), sum.c_str(),
                limit.max * kToDeg);
  }
}

void printToolPositionerHome(const Cell& cell) {
  std::printf("tool %d: TCP in the flange frame %s\n", cell.tool.number,
              xyzRpy(cell.tool.tcp).c_str());
  const PositionerDescription& p = cell.positioner;
  std::printf("positioner: %s\n  base in world: %s\n", p.model.c_str(), xyzRpy(p.base).c_str());
  std::printf("  tilt axis through %s mm along %s: [%.1f, %.1f] deg, %.1f deg/s\n",
              vec(p.tiltAxisPoint, "%.1f").c_str(), vec(p.tiltAxisDirection).c_str(),
              p.tilt.limit.min * kToDeg, p.tilt.limit.max * kToDeg, p.tilt.limit.maxSpeed * kToDeg);
  if (p.rotation.endless) {
    std::printf("  rotation axis through %s mm along %s: endless, %.1f deg/s\n",
                vec(p.rotationAxisPoint, "%.1f").c_str(), vec(p.rotationAxisDirection).c_str(),
                p.rotation.limit.maxSpeed * kToDeg);
  } else {
    std::printf("  rotation axis through %s mm along %s: [%.1f, %.1f] deg, %.1f deg/s\n",
                vec(p.rotationAxisPoint, "%.1f").c_str(), vec(p.rotationAxisDirection).c_str(),
                p.rotation.limit.min * kToDeg, p.rotation.limit.max * kToDeg,
                p.rotation.limit.maxSpeed * kToDeg);
  }
  const Pose tcp = computeFlangePose(cell.robot, cell.home.robot) * cell.tool.tcp;
  std::printf("home: robot %s; TCP %s in world, %s in the controller's robot frame\n",
              joints(cell.home.robot).c_str(), xyzRpy(cell.robot.base * tcp).c_str(),
              xyzRpy(cell.robot.controllerFrame.inverse() * tcp).c_str());
}

int runCellCheck(const CellCheckArguments& args) {
  TerminalProgress display(false);
  try {
    const Cell cell = readCell(args.cell);
    std::printf("cell: %s (%s)\n", cell.name.c_str(), args.cell.c_str());
    printRobot(cell);
    printToolPositionerHome(cell);
    printSources(args.cell);
    for (const std::string& note : cell.notes) std::printf("note: %s\n", note.c_str());
    if (const auto folded = findFoldedPose(cell.robot)) {
      return reportFailure(
          display, kExitInvalidInput,
          args.cell +
              ": the ranges robot/joints/1 and robot/joints/2 (joints 2 and 3) allow a "
              "folded arm (elbow angle " +
              std::to_string(
                  static_cast<int>(std::round(elbowAngle(cell.robot, *folded) * kToDeg))) +
              " deg at joints " + joints(*folded) +
              ") and no robot/interference limit excludes it; add the robot's interference limit "
              "(resources/cells/README.md, \"Interference limits\") or narrow joint 3's range");
    }
    std::printf("check: joints 2 and 3 cannot fold the arm within the limits\n");
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, "", kJobOutOfMemoryMessage);
  }
}

}  // namespace

void addCellCommand(CLI::App& app, CommandList& commands) {
  CLI::App* cell = app.add_subcommand("cell", "Inspect a robot cell description.");
  cell->require_subcommand(1);
  auto args = std::make_shared<CellCheckArguments>();
  CLI::App* check = cell->add_subcommand(
      "check",
      "Print a cell's frames (world, robot base, the controller's robot frame, flange, TCP), the\n"
      "arm's reach, joint and positioner limits, interference limits, home and sources; exit 2\n"
      "when it cannot be read or joints 2 and 3 can fold the arm with no interference limit.");
  check->add_option("CELL", args->cell, "The cell description (JSON, resources/cells/*.json).")
      ->required();
  commands.push_back({check, [args] { return runCellCheck(*args); }});
}

}  // namespace curvedslicer::cli
