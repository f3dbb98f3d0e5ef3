// Yaskawa INFORM writer (see jbi_writer.hpp). Phases: "export" (split into jobs, then positions
// and instructions of each job).
#include "curvedslicer/export/jbi_writer.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

struct JobPlan {
  std::string name;
  IndexRange points;
};

/// The input confirming the arc (controller/jbi arc_wait_input), 0 = none.
int arcWaitInput(const Cell& cell) {
  return cell.controller.jbi ? cell.controller.jbi->arcWaitInput : 0;
}

/// Instruction lines of point i: the motion, ARCON (and the arc wait) after a path start, ARCOF
/// and TIMER after a path end.
std::size_t instructionLines(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  std::size_t lines = 1;
  if (p.pathStart) lines += arcWaitInput(cell) > 0 ? 2 : 1;
  if (p.pathEnd) ++lines;
  if (dwellAfter(motion, cell, i) > 0.0) ++lines;
  return lines;
}

/// ///RCONF: wrist flip, elbow down, back, then R (joint 4), T (joint 6), S (joint 1) at or beyond
/// 180°, padded with zeros to 8 fields (NX100) or 24 (DX100 and later, names longer than 8
/// characters). `c` is the point's configuration (its weld's within a weld).
std::string rconfLine(const Cell& cell, const RobotConfiguration& c) {
  const int fields = cell.exportOptions.maxNameLength > 8 ? 24 : 8;
  const int values[6] = {(c.branch & 4) ? 1 : 0, (c.branch & 2) ? 1 : 0, (c.branch & 1) ? 1 : 0,
                         c.beyond180[3] ? 1 : 0, c.beyond180[5] ? 1 : 0, c.beyond180[0] ? 1 : 0};
  std::string line = "///RCONF ";
  for (int k = 0; k < fields; ++k) {
    if (k > 0) line += ',';
    line += k < 6 ? static_cast<char>('0' + values[k]) : '0';
  }
  return line;
}

void appendIndex(std::string& out, const char* prefix, std::size_t index) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%s%05zu", prefix, index);
  out += buf;
}

std::string arcOnLine(const Cell& cell) {
  const ProcessDescription& pr = cell.process;
  if (pr.arcControl == ArcControl::ConditionFile) {
    return "ARCON ASF#(" + std::to_string(pr.arcStartCondition) + ")";
  }
  std::string s = "ARCON AC=";
  appendFixed(s, pr.current, 0);
  s += " AV=";
  appendFixed(s, pr.voltage, 1);
  s += " T=";
  appendFixed(s, pr.arcStartTime, 2);
  return s;
}

std::string arcOffLine(const Cell& cell) {
  const ProcessDescription& pr = cell.process;
  if (pr.arcControl == ArcControl::ConditionFile) {
    return "ARCOF AEF#(" + std::to_string(pr.arcEndCondition) + ")";
  }
  return "ARCOF";
}

/// One job file holding the points `range` (absolute indices into motion.points).
ExportFile writeJob(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                    const std::string& name, IndexRange range, const Progress& progress,
                    const PointConfigurations& configurations, std::size_t& motionCount,
                    std::size_t& arcCount) {
  const ExportDescription& ex = cell.exportOptions;
  const bool pulse = ex.positionType == PositionType::Pulse;
  const std::size_t n = range.size();
  ProgramText text(ex.lineEnding);
  text.line("/JOB");
  text.line("//NAME " + name);
  text.line("//POS");
  text.line("///NPOS " + std::to_string(n) + ",0," + std::to_string(n) + ",0,0,0");
  text.line("///TOOL " + std::to_string(cell.tool.number));
  if (pulse) {
    text.line("///POSTYPE PULSE");
    text.line("///PULSE");
  } else {
    text.line("///POSTYPE BASE");
    text.line("///RECTAN");
  }
  // BASE positions are in the controller's robot coordinates (on the S axis at the height of
  // the L axis for Yaskawa), not in the model's robot base frame.
  const Pose robotFrameInverse = cell.robot.controllerFrame.inverse();
  std::string lastRconf;
  for (std::size_t k = 0; k < n; ++k) {
    const MotionPoint& p = motion.points[range.begin + k];
    if (!pulse) {
      std::string rconf = rconfLine(cell, configurations.at(range.begin + k));
      if (rconf != lastRconf) {
        text.line(rconf);
        lastRconf = std::move(rconf);
      }
    }
    std::string& b = text.buffer();
    appendIndex(b, "C", k);
    b += '=';
    if (pulse) {
      const auto pulses = robotPulses(cell.robot, p.joints);
      for (int j = 0; j < 6; ++j) {
        if (j > 0) b += ',';
        appendInt(b, pulses[j]);
      }
    } else {
      const XyzRpy c = toXyzRpy(robotFrameInverse * p.toolInRobotBase);
      appendList(b, {c.x, c.y, c.z}, 3);
      b += ',';
      appendList(b, {c.roll, c.pitch, c.yaw}, 4);
    }
    text.endLine();
    reportEvery(progress, range.begin + k, motion.points.size());
  }
  text.line("///POSTYPE PULSE");
  text.line("///PULSE");
  for (std::size_t k = 0; k < n; ++k) {
    const MotionPoint& p = motion.points[range.begin + k];
    std::string& b = text.buffer();
    appendIndex(b, "EC", k);
    b += '=';
    appendInt(b, positionerPulses(cell.positioner.tilt, p.a1));
    b += ',';
    appendInt(b, positionerPulses(cell.positioner.rotation, p.a2));
    text.endLine();
  }
  text.line("//INST");
  text.line("///DATE " + options.date);
  text.line(pulse ? "///ATTR SC,RW" : "///ATTR SC,RW,RJ");
  text.line("///GROUP1 RB1");
  text.line("///GROUP2 ST1");
  text.line("NOP");
  const std::string arcOn = arcOnLine(cell);
  const std::string arcOff = arcOffLine(cell);
  const int arcWait = arcWaitInput(cell);
  const int speedDigits = speedDecimals(cell);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = range.begin + k;
    const MotionPoint& p = motion.points[i];
    std::string& b = text.buffer();
    if (isJointMove(motion, i)) {
      const double percent = jointSpeedPercent(motion, cell, i);
      b += "MOVJ ";
      appendIndex(b, "C", k);
      b += " VJ=";
      appendFixed(b, percent, 2);
      b += " +MOVJ ";
      appendIndex(b, "EC", k);
      b += " VJ=";
      appendFixed(b, percent, 2);
    } else {
      b += ex.coordinated ? "SMOVL " : "MOVL ";
      appendIndex(b, "C", k);
      b += " V=";
      appendSpeed(b, controllerSpeed(cell, p.speed), speedDigits, speedReduced(p));
      b += " +MOVJ ";
      appendIndex(b, "EC", k);
    }
    text.endLine();
    ++motionCount;
    if (p.pathStart) {
      text.line(arcOn);
      if (arcWait > 0) text.line("WAIT IN#(" + std::to_string(arcWait) + ")=ON");
      ++arcCount;
    }
    if (p.pathEnd) text.line(arcOff);
    const double dwell = dwellAfter(motion, cell, i);
    if (dwell > 0.0) {
      std::string& t = text.buffer();
      t += "TIMER T=";
      appendFixed(t, dwell, 2);
      text.endLine();
    }
  }
  text.line("END");
  ExportFile file;
  file.name = name + ".JBI";
  file.lines = text.lineCount();
  file.text = text.take();
  return file;
}

}  // namespace

ExportResult JbiWriter::write(const MotionPlan& motion, const Cell& cell,
                              const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "JBI");
  checkJointLimits(motion, cell);
  const ExportDescription& ex = cell.exportOptions;
  if (ex.positionType == PositionType::User) {
    throw InvalidInput(
        "JBI export cannot write robot positions in a user frame: position_type user; the cell "
        "does not define the user frame, use pulse or base");
  }
  if (ex.positionType == PositionType::Pulse && cell.robot.pulsesPerDegree.size() != 6) {
    throw InvalidInput(
        "JBI export with position type pulse needs the robot's pulses per degree: " +
        std::to_string(cell.robot.pulsesPerDegree.size()) +
        " values; add robot/pulses_per_degree to the cell or use position type base");
  }
  if (ex.maxLinesPerJob < 3) {
    throw InvalidInput("maximum lines per job is too small for a job (NOP, a motion, END): " +
                       std::to_string(ex.maxLinesPerJob) + "; use e.g. 2000");
  }
  const std::size_t nameLimit = static_cast<std::size_t>(std::max(1, ex.maxNameLength));
  const std::string mainName = makeProgramName(baseProgramName(cell, options), nameLimit, true);

  // ---- split into jobs -----------------------------------------------------------------------
  const std::size_t count = motion.points.size();
  std::vector<std::size_t> costs(count);
  std::vector<bool> breaks(count);
  std::size_t total = 2;  // NOP, END
  for (std::size_t i = 0; i < count; ++i) {
    costs[i] = instructionLines(motion, cell, i);
    breaks[i] = !motion.points[i].arcOn;  // an arc-off move: a path start, retract, travel, …
    total += costs[i];
  }
  const std::size_t limit = static_cast<std::size_t>(ex.maxLinesPerJob);
  std::vector<JobPlan> jobs;
  if (total <= limit) {
    jobs.push_back({mainName, {0, count}});
  } else {
    const std::vector<IndexRange> chunks = splitAtLimit(costs, breaks, limit - 2);
    if (chunks.size() + 2 > limit) {
      throw InvalidInput("the program needs more sub-jobs than the main job can call: " +
                         std::to_string(chunks.size()) + " sub-jobs, at most " +
                         std::to_string(limit - 2) + " lines; raise max_lines_per_job");
    }
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      std::string name = makeSubJobName(mainName, k + 1, chunks.size(), nameLimit);
      if (name == mainName) {
        throw InvalidInput("a sub-job would have the main job's name: " + name +
                           "; choose a job name that does not end in digits");
      }
      jobs.push_back({std::move(name), chunks[k]});
    }
  }

  // ---- write ---------------------------------------------------------------------------------
  ExportResult result;
  result.format = ExportFormat::Jbi;
  const PointConfigurations configurations(motion);
  if (ex.positionType != PositionType::Pulse) {  // pulses state joints, no configuration
    if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
      result.warnings.push_back(std::move(mismatch));
    }
  }
  if (jobs.size() > 1) {
    ProgramText text(ex.lineEnding);
    text.line("/JOB");
    text.line("//NAME " + mainName);
    text.line("//POS");
    text.line("///NPOS 0,0,0,0,0,0");
    text.line("//INST");
    text.line("///DATE " + options.date);
    text.line("///ATTR SC,RW");
    text.line("///GROUP1 RB1");
    text.line("///GROUP2 ST1");
    text.line("NOP");
    for (const JobPlan& job : jobs) text.line("CALL JOB:" + job.name);
    text.line("END");
    ExportFile file;
    file.name = mainName + ".JBI";
    file.lines = text.lineCount();
    file.text = text.take();
    result.files.push_back(std::move(file));
    result.warnings.push_back("the program is split into " + std::to_string(jobs.size()) +
                              " sub-jobs of at most " + std::to_string(limit) +
                              " instruction lines, called from " + mainName);
  }
  for (const JobPlan& job : jobs) {
    result.files.push_back(writeJob(motion, cell, options, job.name, job.points, progress,
                                    configurations, result.motionCount, result.arcCount));
    const MotionPoint& last = motion.points[job.points.end - 1];
    if (job.points.end < count && motion.points[job.points.end].arcOn && jobs.size() > 1) {
      result.warnings.push_back("path " + std::to_string(last.path) + " of layer " +
                                std::to_string(last.layer) +
                                " is longer than a job and continues in the next job");
    }
  }
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
