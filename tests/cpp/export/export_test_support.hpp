// Test-side helpers for the exporter tests: small plans (a turbine-base-like cone surface, a tiny
// two-layer plan), readers that parse each format back, and the reconstruction of the part-frame
// point from what a program states (positions, pulses, external axes) through forward kinematics.
// The readers are deliberately independent of the writers: they parse text only.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"

namespace curvedslicer::testing {

inline constexpr double kPiT = 3.14159265358979323846;
inline constexpr double kDegT = kPiT / 180.0;

/// A turbine-base-like plan: one layer of `circles` closed circular paths climbing the side of a
/// cone (radius r0 at z = 0 to r1 at z = height, part frame), `pointsPerCircle` points each.
/// Normal: the cone's outward surface normal. V: towards the previous bead — down the cone's
/// generatrix to the circle below; for the first circle straight down onto the substrate.
inline Plan makeConePlan(int circles, int pointsPerCircle, double r0 = 100.0, double r1 = 50.0,
                         double height = 55.0) {
  Plan plan;
  plan.model = "cone";
  plan.start = "plane:bottom";
  plan.parameters.layerThickness = 1.65;
  PlanLayer layer;
  layer.index = 0;
  const double slope = (r1 - r0) / height;  // dr/dz
  const Vec3 axisDown(0, 0, -1);
  for (int c = 0; c < circles; ++c) {
    const double z = height * c / std::max(1, circles - 1) * 0.9;
    const double r = r0 + slope * z;
    PlanPath path;
    path.layer = 0;
    path.index = c;
    path.closed = true;
    for (int k = 0; k < pointsPerCircle; ++k) {
      const double t = 2.0 * kPiT * k / pointsPerCircle;
      const Vec3 radial(std::cos(t), std::sin(t), 0.0);
      PathPoint p;
      p.position = r * radial + Vec3(0, 0, z);
      p.normal = (radial - slope * Vec3::UnitZ()).normalized();
      p.deposition = c == 0 ? axisDown : Vec3(-(slope * radial + Vec3::UnitZ()).normalized());
      path.points.push_back(p);
    }
    path.length = 2.0 * kPiT * r;
    layer.paths.push_back(path);
  }
  plan.layers.push_back(layer);
  return plan;
}

/// A tiny plan for golden files: two flat layers of two short straight paths each, V tilted a
/// little so the positioner moves.
inline Plan makeSmallPlan() {
  Plan plan;
  plan.model = "small";
  plan.start = "plane:bottom";
  for (int l = 0; l < 2; ++l) {
    PlanLayer layer;
    layer.index = l;
    layer.height = 1.5 * (l + 1);
    for (int k = 0; k < 2; ++k) {
      PlanPath path;
      path.layer = l;
      path.index = k;
      for (int i = 0; i < 3; ++i) {
        PathPoint p;
        p.position = Vec3(-20.0 + 10.0 * i, -5.0 + 10.0 * k, 1.5 * (l + 1));
        p.normal = Vec3::UnitZ();
        p.deposition = Vec3(0.1 * (i - 1), 0.05 * k, -1.0).normalized();
        path.points.push_back(p);
      }
      path.length = 20.0;
      layer.paths.push_back(path);
    }
    plan.layers.push_back(layer);
  }
  return plan;
}

/// Splits `line` at `sep`, trimming spaces and tabs.
inline std::vector<std::string> splitFields(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else if (c != ' ' && c != '\t') {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

/// Lines of `text` split at "\r\n" (if `crlf`) or "\n"; `ok` false if an ending does not match.
inline std::vector<std::string> splitLines(const std::string& text, bool crlf, bool* ok) {
  std::vector<std::string> lines;
  *ok = true;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    if (nl == std::string::npos) {
      *ok = false;  // no ending after the last line
      lines.push_back(text.substr(start));
      break;
    }
    std::size_t end = nl;
    const bool hasCr = nl > start && text[nl - 1] == '\r';
    if (crlf != hasCr) *ok = false;
    if (hasCr) --end;
    const std::string line = text.substr(start, end - start);
    if (line.find('\r') != std::string::npos) *ok = false;
    lines.push_back(line);
    start = nl + 1;
  }
  return lines;
}

/// The value after `key` (e.g. "X ") in `text` up to the next ',' '}' or space.
inline double valueAfter(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) {
    ADD_FAILURE() << "missing '" << key << "' in: " << text;
    return 0.0;
  }
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

// ---- JBI --------------------------------------------------------------------------------------

struct JbiJob {
  std::string name;
  std::vector<long> npos;                       ///< the 6 NPOS numbers
  std::map<int, std::vector<double>> c, ec;     ///< declared positions by number
  std::map<int, int> cDeclared, ecDeclared;     ///< how often each was declared
  std::map<int, std::vector<int>> rconfBefore;  ///< RCONF in force for each C
  std::string cPosType;                         ///< "PULSE" or "BASE"
  std::vector<std::string> instructions;        ///< NOP … END
  bool crlf = true;
};

/// Parses one job file; failures are reported through gtest.
inline JbiJob parseJbi(const std::string& text) {
  JbiJob job;
  bool ok = false;
  const auto lines = splitLines(text, true, &ok);
  job.crlf = ok;
  enum { kHeader, kPos, kInst } section = kHeader;
  std::string postype;
  std::vector<int> rconf;
  bool sawEc = false;
  for (const std::string& line : lines) {
    if (line.rfind("//NAME ", 0) == 0) {
      job.name = line.substr(7);
    } else if (line == "//POS") {
      section = kPos;
    } else if (line == "//INST") {
      section = kInst;
    } else if (line.rfind("///NPOS ", 0) == 0) {
      for (const auto& f : splitFields(line.substr(8), ',')) job.npos.push_back(std::stol(f));
    } else if (line.rfind("///POSTYPE ", 0) == 0) {
      postype = line.substr(11);
    } else if (line.rfind("///RCONF ", 0) == 0) {
      rconf.clear();
      for (const auto& f : splitFields(line.substr(9), ',')) rconf.push_back(std::stoi(f));
    } else if (section == kPos && (line[0] == 'C' || line.rfind("EC", 0) == 0)) {
      const bool isEc = line.rfind("EC", 0) == 0;
      const std::size_t eq = line.find('=');
      const int number = std::stoi(line.substr(isEc ? 2 : 1, eq - (isEc ? 2 : 1)));
      std::vector<double> values;
      for (const auto& f : splitFields(line.substr(eq + 1), ',')) values.push_back(std::stod(f));
      if (isEc) {
        sawEc = true;
        EXPECT_EQ(postype, "PULSE") << "station positions must be pulses";
        job.ec[number] = values;
        ++job.ecDeclared[number];
      } else {
        EXPECT_FALSE(sawEc) << "robot positions after station positions";
        job.cPosType = postype;
        job.c[number] = values;
        job.rconfBefore[number] = rconf;
        ++job.cDeclared[number];
      }
    } else if (section == kInst && !line.empty() && line.rfind("///", 0) != 0) {
      job.instructions.push_back(line);
    }
  }
  return job;
}

/// The numbers of Cnnnnn / ECnnnnn references in an instruction.
inline void collectReferences(const std::string& line, std::vector<int>& c, std::vector<int>& ec) {
  std::istringstream in(line);
  std::string tok;
  while (in >> tok) {
    if (tok.rfind("EC", 0) == 0 && tok.size() == 7) {
      ec.push_back(std::stoi(tok.substr(2)));
    } else if (tok[0] == 'C' && tok.size() == 6 &&
               std::isdigit(static_cast<unsigned char>(tok[1]))) {
      c.push_back(std::stoi(tok.substr(1)));
    }
  }
}

/// The cell with the part where the motion placed it (MotionPlan::tableToPart, the placement
/// rule of robot/placement.hpp): what an independent reader of the program must assume.
inline Cell placedCell(Cell cell, const MotionPlan& motion) {
  cell.positioner.tableToPart = motion.tableToPart;
  return cell;
}

/// Part-frame position of the TCP from a TCP pose in the robot base frame and the positioner
/// angles (model convention).
inline Vec3 partPointFromRobotBase(const Cell& cell, const Pose& tcpInBase, double a1, double a2) {
  const Pose world = cell.robot.base * tcpInBase;
  return computePartInWorld(cell.positioner, a1, a2).inverse() * world.translation();
}

/// The controller's Cartesian robot frame in the robot base frame, written out here from the
/// vendors' definitions independently of the writers: Yaskawa's robot coordinates and Fanuc's world
/// frame lie on joint 1's axis at the height of joint 2 (the model's c1 above the base), KUKA's and
/// ABB's base frames at the foot. A cell of a known vendor must state that frame
/// (robot/controller_frame); a cell without vendor is taken at its word.
inline Pose controllerRobotFrame(const Cell& cell) {
  Pose frame = Pose::Identity();
  switch (cell.vendor) {
    case RobotVendor::Yaskawa:
    case RobotVendor::Fanuc:
      frame.translation() = Vec3(0, 0, cell.robot.kinematics.c1);
      break;
    case RobotVendor::Kuka:
    case RobotVendor::Abb:
      break;
    case RobotVendor::Unknown:
      return cell.robot.controllerFrame;
  }
  EXPECT_TRUE(cell.robot.controllerFrame.isApprox(frame, 1e-12))
      << "the cell's robot/controller_frame is not its vendor's robot frame: z "
      << cell.robot.controllerFrame.translation().z() << " mm instead of "
      << frame.translation().z();
  return frame;
}

/// Part-frame position of the TCP from a Cartesian position in the controller's robot frame.
inline Vec3 partPointFromControllerFrame(const Cell& cell, const Pose& tcpInRobotFrame, double a1,
                                         double a2) {
  return partPointFromRobotBase(cell, controllerRobotFrame(cell) * tcpInRobotFrame, a1, a2);
}

/// Part-frame position of the TCP from robot joint angles in controller degrees (a joint target:
/// the home pose) through forward kinematics, and the positioner angles.
inline Vec3 partPointFromJointDegrees(const Cell& cell, const std::vector<double>& degrees,
                                      double a1, double a2) {
  EXPECT_EQ(degrees.size(), 6u) << "a joint target states six robot joints";
  JointVector joints{};
  for (std::size_t j = 0; j < 6 && j < degrees.size(); ++j) joints[j] = degrees[j] * kDegT;
  const Pose tcpInBase = computeFlangePose(cell.robot, joints) * cell.tool.tcp;
  return partPointFromRobotBase(cell, tcpInBase, a1, a2);
}

inline Vec3 partPointFromTable(const Cell& cell, const Pose& tcpInTable, double a1, double a2) {
  const Pose world = computeTableInWorld(cell.positioner, a1, a2) * tcpInTable;
  return computePartInWorld(cell.positioner, a1, a2).inverse() * world.translation();
}

inline Vec3 partPointFromWorld(const Cell& cell, const Vec3& world, double a1, double a2) {
  return computePartInWorld(cell.positioner, a1, a2).inverse() * world;
}

/// Positioner model angles from controller pulses.
inline double tiltFromPulses(const Cell& cell, double pulses) {
  return cell.positioner.tilt.sign * pulses / cell.positioner.tilt.pulsesPerDegree * kDegT;
}
inline double rotationFromPulses(const Cell& cell, double pulses) {
  return cell.positioner.rotation.sign * pulses / cell.positioner.rotation.pulsesPerDegree * kDegT;
}

/// Pose from x y z (mm) and roll pitch yaw (deg), R = Rz·Ry·Rx.
inline Pose poseFromXyzRpy(double x, double y, double z, double roll, double pitch, double yaw) {
  return makePose(Vec3(x, y, z), Vec3(roll, pitch, yaw) * kDegT);
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace curvedslicer::testing
