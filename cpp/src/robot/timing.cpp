// Time parameterisation (robot/timing.hpp). Phases: dwells per point, move durations and
// speeds, speed-reduction stretches, estimates.
#include "curvedslicer/robot/timing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace curvedslicer {
namespace {

constexpr int kNominal = 8;

std::string fmt(double value, int precision) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

/// Dwell after each point (s): pathDwell at every path end, layerDwell after each layer's last
/// path (a layer without paths: at the end of the path before it). `leading` gets the dwell of
/// layers before the first path. `closes[i]` is the layer whose last path ends at point i (-1
/// elsewhere): where a layer shorter than the minimum layer time waits the rest.
std::vector<double> computeDwells(const MotionPlan& motion, const ProcessDescription& process,
                                  double& leading, std::vector<int>& closes) {
  std::vector<double> dwell(motion.points.size(), 0.0);
  closes.assign(motion.points.size(), -1);
  leading = 0.0;
  std::size_t span = 0;
  double* lastEnd = &leading;
  for (std::size_t l = 0; l < motion.layers.size(); ++l) {
    std::size_t end = 0;
    bool any = false;
    for (; span < motion.paths.size() && motion.paths[span].layer == static_cast<int>(l); ++span) {
      end = motion.paths[span].end - 1;
      any = true;
      lastEnd = &dwell[end];
      *lastEnd += process.pathDwell;
    }
    if (any) closes[end] = static_cast<int>(l);
    *lastEnd += process.layerDwell;
  }
  return dwell;
}

/// Duration of the move from `a` to `b` and the axis that sets it (0..7, kNominal).
struct MoveTime {
  double seconds = 0.0;
  double nominal = 0.0;
  double length = 0.0;  // mm the speed refers to
  int axis = kNominal;
};

MoveTime computeMoveTime(const MotionPoint& a, const MotionPoint& b, const Cell& cell,
                         const std::array<double, 8>& inverseSpeed, bool limitAxes) {
  MoveTime t;
  const double partLength = (b.position - a.position).norm();
  if (b.arcOn) {
    t.length = partLength;
    // The weld speed planMotion set for the move (the cell's, or the bead model's).
    t.nominal = partLength / (b.nominalSpeed > 0.0 ? b.nominalSpeed : cell.process.weldSpeed);
  } else {
    const double worldLength = (b.toolInWorld.translation() - a.toolInWorld.translation()).norm();
    t.length = std::max(partLength, worldLength);
    t.nominal = t.length / cell.process.travelSpeed;
  }
  t.seconds = t.nominal;
  if (!limitAxes) return t;
  for (int j = 0; j < 6; ++j) {
    const double s = std::abs(b.joints[j] - a.joints[j]) * inverseSpeed[j];
    if (s > t.seconds) {
      t.seconds = s;
      t.axis = j;
    }
  }
  const double tilt = std::abs(b.a1 - a.a1) * inverseSpeed[6];
  if (tilt > t.seconds) {
    t.seconds = tilt;
    t.axis = 6;
  }
  const double rotation = std::abs(b.a2 - a.a2) * inverseSpeed[7];
  if (rotation > t.seconds) {
    t.seconds = rotation;
    t.axis = 7;
  }
  return t;
}

/// Extends the open stretch with the reduced move ending at point i, or starts a new one.
void recordReduction(const MotionPlan& motion, std::size_t i, double speed, int axis,
                     std::vector<SpeedReduction>& out, std::size_t& lastReduced) {
  const MotionPoint& b = motion.points[i];
  if (!out.empty() && lastReduced + 1 == i && out.back().layer == b.layer &&
      out.back().path == b.path) {
    SpeedReduction& r = out.back();
    r.lastIndex = b.index;
    if (speed < r.minSpeed) {
      r.minSpeed = speed;
      r.axis = std::string(axisName(axis));
    }
  } else {
    out.push_back(
        {b.layer, b.path, motion.points[i - 1].index, b.index, speed, std::string(axisName(axis))});
  }
  lastReduced = i;
}

std::string summariseReductions(const std::vector<SpeedReduction>& reductions, std::size_t moves,
                                double weldSpeed) {
  std::vector<const SpeedReduction*> lowest;
  for (const SpeedReduction& r : reductions) lowest.push_back(&r);
  const std::size_t examples = std::min<std::size_t>(3, lowest.size());
  std::partial_sort(
      lowest.begin(), lowest.begin() + static_cast<long>(examples), lowest.end(),
      [](const SpeedReduction* a, const SpeedReduction* b) { return a->minSpeed < b->minSpeed; });
  std::string text =
      "weld speed reduced below " + fmt(weldSpeed, 2) +
      " mm/s to keep every axis within its speed limit: " + std::to_string(reductions.size()) +
      " stretch(es), " + std::to_string(moves) + " weld move(s); lowest e.g. ";
  for (std::size_t k = 0; k < examples; ++k) {
    const SpeedReduction& r = *lowest[k];
    text += (k ? "; " : "") + std::string("layer ") + std::to_string(r.layer) + " path " +
            std::to_string(r.path) + " points " + std::to_string(r.firstIndex) + ".." +
            std::to_string(r.lastIndex) + " at " + fmt(r.minSpeed, 2) + " mm/s (" +
            fmt(100.0 * r.minSpeed / weldSpeed, 1) + "%, " + r.axis + ")";
  }
  return text;
}

/// Time fields of the estimates from the parameterised moves.
void setEstimates(MotionPlan& motion, const ProcessDescription& process,
                  const std::vector<double>& arc, const std::vector<double>& travel,
                  const std::vector<double>& travelLength, const std::vector<double>& dwell,
                  const std::vector<double>* wire) {
  constexpr double kPi = 3.14159265358979323846;
  const double area = kPi * 0.25 * process.wireDiameter * process.wireDiameter;
  MotionEstimate total;
  for (std::size_t l = 0; l < motion.layers.size(); ++l) {
    MotionEstimate& e = motion.layers[l];
    e.arcTime = arc[l];
    e.travelTime = travel[l];
    e.travelLength = travelLength[l];
    e.dwellTime = dwell[l];
    e.totalTime = e.arcTime + e.travelTime + e.dwellTime;
    // Per-move wire feed (bead model) where it varies, else the cell's for the whole arc time.
    e.wireLength = wire ? (*wire)[l] : process.wireFeed * 1000.0 / 60.0 * e.arcTime;
    e.depositedVolume = area * e.wireLength * process.depositionEfficiency;
    e.depositedMass = e.depositedVolume * process.wireDensity / 1000.0;
    total.beadLength += e.beadLength;
    total.arcTime += e.arcTime;
    total.travelLength += e.travelLength;
    total.travelTime += e.travelTime;
    total.dwellTime += e.dwellTime;
    total.coolingWait += e.coolingWait;
    total.cooledLayers += e.cooledLayers;
    total.totalTime += e.totalTime;
    total.wireLength += e.wireLength;
    total.depositedVolume += e.depositedVolume;
    total.depositedMass += e.depositedMass;
    total.paths += e.paths;
    total.points += e.points;
  }
  motion.total = total;
}

}  // namespace

std::string_view axisName(int axis) {
  static constexpr std::string_view kNames[] = {
      "robot joint 1", "robot joint 2", "robot joint 3",        "robot joint 4",
      "robot joint 5", "robot joint 6", "positioner tilt (a1)", "positioner rotation (a2)",
      "weld speed"};
  return kNames[std::clamp(axis, 0, kNominal)];
}

void parameteriseTime(MotionPlan& motion, const Cell& cell, const TimingOptions& options) {
  std::array<double, 8> inverseSpeed{};
  for (int j = 0; j < 6; ++j) inverseSpeed[j] = 1.0 / cell.robot.joints[j].maxSpeed;
  inverseSpeed[6] = 1.0 / cell.positioner.tilt.limit.maxSpeed;
  inverseSpeed[7] = 1.0 / cell.positioner.rotation.limit.maxSpeed;
  const std::size_t layerCount = motion.layers.size();
  std::vector<double> arc(layerCount, 0.0), travel(layerCount, 0.0), travelLength(layerCount, 0.0);
  std::vector<double> dwellOfLayer(layerCount, 0.0);
  std::vector<double> wire(layerCount, 0.0);  // mm of wire fed per layer at per-move feeds
  bool variableFeed = false;
  double leading = 0.0;
  std::vector<int> closes;
  const std::vector<double> dwell = computeDwells(motion, cell.process, leading, closes);
  // When each layer's first weld point is reached: its layer time runs from there to the end
  // of the dwell after its last path.
  std::vector<double> layerStart(layerCount, 0.0);
  std::vector<int> opens(motion.points.size(), -1);
  // the last layer waits for nothing: no layer is welded onto it
  const int lastWelded = motion.paths.empty() ? -1 : motion.paths.back().layer;
  for (std::size_t k = 0; k < motion.paths.size(); ++k) {
    const MotionPathSpan& span = motion.paths[k];
    const bool first = k == 0 || motion.paths[k - 1].layer != span.layer;
    if (first && span.layer >= 0 && span.begin < opens.size()) opens[span.begin] = span.layer;
  }
  for (std::size_t l = 0; l < layerCount; ++l) {
    dwellOfLayer[l] = cell.process.layerDwell;
    motion.layers[l].coolingWait = 0.0;
    motion.layers[l].cooledLayers = 0;
  }
  for (const MotionPathSpan& span : motion.paths) {
    if (span.layer >= 0 && static_cast<std::size_t>(span.layer) < layerCount) {
      dwellOfLayer[static_cast<std::size_t>(span.layer)] += cell.process.pathDwell;
    }
  }
  motion.speedReductions.clear();
  std::size_t reducedMoves = 0, lastReduced = 0;
  const double tolerance = 1.0 + 1e-12;
  double time = leading;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    MotionPoint& b = motion.points[i];
    b.flags &= ~static_cast<std::uint32_t>(kMotionSpeedReduced);
    if (i == 0) {
      b.time = time;
      if (opens[i] >= 0 && static_cast<std::size_t>(opens[i]) < layerCount) {
        layerStart[static_cast<std::size_t>(opens[i])] = time;
      }
      b.speed = cell.process.travelSpeed;
      continue;
    }
    const MotionPoint& a = motion.points[i - 1];
    const MoveTime move = computeMoveTime(a, b, cell, inverseSpeed, options.limitAxes);
    double wait = 0.0;  // for the minimum layer time, after the layer's dwells
    if (const int closed = closes[i - 1]; closed >= 0 && closed != lastWelded) {
      const double layerTime = time + dwell[i - 1] - layerStart[static_cast<std::size_t>(closed)];
      if (layerTime < cell.process.minLayerTime) {
        wait = cell.process.minLayerTime - layerTime;
        MotionEstimate& e = motion.layers[static_cast<std::size_t>(closed)];
        e.coolingWait = wait;
        e.cooledLayers = 1;
        dwellOfLayer[static_cast<std::size_t>(closed)] += wait;
      }
    }
    time += dwell[i - 1] + wait + move.seconds;
    b.time = time;
    if (opens[i] >= 0 && static_cast<std::size_t>(opens[i]) < layerCount) {
      layerStart[static_cast<std::size_t>(opens[i])] = time;
    }
    const double weldSpeed = b.nominalSpeed > 0.0 ? b.nominalSpeed : cell.process.weldSpeed;
    const double nominalSpeed = b.arcOn ? weldSpeed : cell.process.travelSpeed;
    b.speed =
        move.seconds > 0.0 ? std::min(nominalSpeed, move.length / move.seconds) : nominalSpeed;
    const std::size_t layer =
        std::min(static_cast<std::size_t>(std::max(b.layer, 0)), layerCount ? layerCount - 1 : 0);
    if (b.arcOn) {
      if (layerCount) arc[layer] += move.seconds;
      if (layerCount) wire[layer] += b.wireFeed * 1000.0 / 60.0 * move.seconds;
      variableFeed = variableFeed || b.wireFeed != cell.process.wireFeed;
      if (move.axis != kNominal && move.seconds > move.nominal * tolerance) {
        b.flags |= kMotionSpeedReduced;
        ++reducedMoves;
        recordReduction(motion, i, b.speed, move.axis, motion.speedReductions, lastReduced);
      }
    } else if (layerCount) {
      travel[layer] += move.seconds;
      travelLength[layer] += (b.position - a.position).norm();
    }
  }
  if (!motion.speedReductions.empty()) {
    motion.warnings.push_back(
        summariseReductions(motion.speedReductions, reducedMoves, cell.process.weldSpeed));
  }
  setEstimates(motion, cell.process, arc, travel, travelLength, dwellOfLayer,
               variableFeed ? &wire : nullptr);
}

}  // namespace curvedslicer
