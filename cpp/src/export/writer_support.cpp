// The writer helpers that are more than a line (see writer_support.hpp): the map from motion
// points to their welds and the joint speed of a planned joint move.
#include "writer_support.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace curvedslicer::export_detail {

std::vector<int> mapPointsToSpans(const MotionPlan& motion) {
  std::vector<int> spans(motion.points.size(), -1);
  for (std::size_t s = 0; s < motion.paths.size(); ++s) {
    const MotionPathSpan& span = motion.paths[s];
    if (span.begin > span.end || span.end > motion.points.size()) {
      throw InvalidInput(
          "motion path " + std::to_string(s) + " (layer " + std::to_string(span.layer) + ", path " +
          std::to_string(span.path) + ") spans points [" + std::to_string(span.begin) + ", " +
          std::to_string(span.end) + ") outside the " + std::to_string(motion.points.size()) +
          " motion points; re-plan the motion (planMotion)");
    }
    for (std::size_t i = span.begin; i < span.end; ++i) {
      if (spans[i] >= 0) {
        throw InvalidInput("motion point " + std::to_string(i) +
                           " lies in two motion paths: " + std::to_string(spans[i]) + " and " +
                           std::to_string(s) + "; re-plan the motion (planMotion)");
      }
      spans[i] = static_cast<int>(s);
    }
  }
  return spans;
}

std::string describeBranchMismatches(const MotionPlan& motion) {
  std::size_t count = 0;
  std::string first;
  for (const MotionPathSpan& span : motion.paths) {
    for (std::size_t i = span.begin; i < span.end && i < motion.points.size(); ++i) {
      const MotionPoint& p = motion.points[i];
      if (p.configuration == span.configuration.branch) continue;
      if (count++ == 0) {
        first = "layer " + std::to_string(p.layer) + " path " + std::to_string(p.path) + " point " +
                std::to_string(p.index) + " has IK branch " + std::to_string(p.configuration) +
                ", its weld states " + std::to_string(span.configuration.branch);
      }
    }
  }
  if (count == 0) return {};
  return std::to_string(count) +
         " weld point(s) lie in another IK branch than the configuration the program states for "
         "their weld, e.g. " +
         first + "; the controller may refuse or flip there: re-plan the motion";
}

std::vector<ProgramPart> splitIntoParts(const MotionPlan& motion,
                                        const std::vector<std::size_t>& costs,
                                        const std::string& mainName, std::size_t limit,
                                        std::size_t headerLines, std::size_t nameLimit,
                                        std::string_view format) {
  const std::size_t count = motion.points.size();
  std::size_t maxCost = 0, total = headerLines;
  std::vector<bool> breaks(count);
  for (std::size_t i = 0; i < count; ++i) {
    breaks[i] = !motion.points[i].arcOn;
    maxCost = std::max(maxCost, costs[i]);
    total += costs[i];
  }
  if (limit < headerLines + maxCost) {
    throw InvalidInput(std::string(format) + " export: the line limit per program is too small: " +
                       std::to_string(limit) + " lines, a program needs up to " +
                       std::to_string(headerLines + maxCost) +
                       " for its header and one point; raise the cell's line limit");
  }
  if (total <= limit) return {{mainName, {0, count}}};
  const std::vector<IndexRange> chunks = splitAtLimit(costs, breaks, limit - headerLines);
  if (chunks.size() + headerLines > limit) {
    throw InvalidInput(std::string(format) +
                       " export: the main program cannot call all sub-programs: " +
                       std::to_string(chunks.size()) + " calls, at most " +
                       std::to_string(limit - headerLines) + " lines; raise the cell's line limit");
  }
  std::vector<ProgramPart> parts;
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    std::string name = makeSubJobName(mainName, k + 1, chunks.size(), nameLimit);
    if (name == mainName) {
      throw InvalidInput(std::string(format) +
                         " export: a sub-program would have the main "
                         "program's name: " +
                         name + "; choose a program name that does not end in digits");
    }
    parts.push_back({std::move(name), chunks[k]});
  }
  return parts;
}

double jointSpeedPercent(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  if (i == 0) return kUnplannedJointSpeedPercent;
  const MotionPoint& from = motion.points[i - 1];
  const MotionPoint& to = motion.points[i];
  const double duration = to.time - from.time - pathEndDwell(motion, cell, i - 1);
  if (!(duration > 0.0)) return kUnplannedJointSpeedPercent;
  double fraction = 0.0;  // of the maximum speed, the fastest axis
  for (int j = 0; j < 6; ++j) {
    const double speed = std::abs(to.joints[j] - from.joints[j]) / duration;
    fraction = std::max(fraction, speed / cell.robot.joints[j].maxSpeed);
  }
  fraction = std::max(fraction,
                      std::abs(to.a1 - from.a1) / duration / cell.positioner.tilt.limit.maxSpeed);
  fraction = std::max(
      fraction, std::abs(to.a2 - from.a2) / duration / cell.positioner.rotation.limit.maxSpeed);
  const double percent = std::ceil(fraction * 100.0 * 100.0 - 1e-9) / 100.0;
  return std::clamp(percent, 1.0, 100.0);
}

}  // namespace curvedslicer::export_detail
