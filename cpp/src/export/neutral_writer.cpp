// Neutral CSV / JSON writer (see neutral_writer.hpp). Phase: "export".
#include "curvedslicer/export/neutral_writer.hpp"

#include <string>

#include <nlohmann/json.hpp>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

constexpr const char* kColumns[] = {"layer",
                                    "path",
                                    "index",
                                    "x_mm",
                                    "y_mm",
                                    "z_mm",
                                    "nx",
                                    "ny",
                                    "nz",
                                    "vx",
                                    "vy",
                                    "vz",
                                    "a1_deg",
                                    "a2_deg",
                                    "j1_deg",
                                    "j2_deg",
                                    "j3_deg",
                                    "j4_deg",
                                    "j5_deg",
                                    "j6_deg",
                                    "speed_mm_s",
                                    "arc_on",
                                    "path_start",
                                    "path_end",
                                    "time_s",
                                    "residual_deg",
                                    "flags",
                                    "wire_feed_m_min",
                                    "weld_schedule",
                                    "bead_width_mm",
                                    "torch_angle_deg",
                                    "travel_angle_deg",
                                    "work_angle_deg",
                                    "gravity_deviation_deg",
                                    "kind"};

/// Wire feed (m/min) of the move arriving at `p`: its own (MotionPoint::wireFeed) or, where not
/// set, the cell's; 0 with the arc off.
double wireFeedOf(const MotionPoint& p, const Cell& cell) {
  if (!p.arcOn) return 0.0;
  return p.wireFeed > 0.0 ? p.wireFeed : cell.process.wireFeed;
}

/// Appends one row of values separated by `sep`; the kind as a bare word (CSV) or a JSON string.
void appendRow(std::string& b, const MotionPoint& p, const Cell& cell, char sep, bool json) {
  b += std::to_string(p.layer);
  b += sep;
  b += std::to_string(p.path);
  b += sep;
  b += std::to_string(p.index);
  const double values[] = {p.position.x(),   p.position.y(),   p.position.z(),   p.normal.x(),
                           p.normal.y(),     p.normal.z(),     p.deposition.x(), p.deposition.y(),
                           p.deposition.z(), p.a1 * kRadToDeg, p.a2 * kRadToDeg};
  for (double v : values) {
    b += sep;
    appendShortest(b, v);
  }
  for (double j : p.joints) {
    b += sep;
    appendShortest(b, j * kRadToDeg);
  }
  b += sep;
  appendShortest(b, p.speed);
  b += sep;
  b += p.arcOn ? '1' : '0';
  b += sep;
  b += p.pathStart ? '1' : '0';
  b += sep;
  b += p.pathEnd ? '1' : '0';
  b += sep;
  appendShortest(b, p.time);
  b += sep;
  appendShortest(b, p.residual * kRadToDeg);
  b += sep;
  b += std::to_string(p.flags);
  b += sep;
  appendShortest(b, wireFeedOf(p, cell));
  b += sep;
  b += std::to_string(p.weldSchedule);
  b += sep;
  appendShortest(b, p.beadWidth);
  // the torch's angle off gravity and its travel (push > 0) / work shares; the deposit's
  // deviation from gravity (the residual of the positioner angles)
  for (double v : {p.torchAngle, p.travelAngle, p.workAngle, p.residual}) {
    b += sep;
    appendShortest(b, v * kRadToDeg);
  }
  b += sep;
  if (json) b += '"';
  b += toString(p.kind);
  if (json) b += '"';
}

}  // namespace

ExportResult NeutralWriter::write(const MotionPlan& motion, const Cell& cell,
                                  const ExportOptions& options, const Progress& progress) const {
  const bool json = format_ == ExportFormat::Json;
  requirePoints(motion, json ? "JSON" : "CSV");
  ProgramText text(LineEnding::Lf);
  if (json) {
    text.line("{");
    text.line("  \"format\": \"curvedslicer-motion\",");
    text.line("  \"version\": 4,");
    text.line("  \"cell\": " + nlohmann::json(cell.name).dump() + ",");
    std::string& c = text.buffer();
    c += "  \"columns\": [";
    for (std::size_t k = 0; k < std::size(kColumns); ++k) {
      if (k > 0) c += ", ";
      c += '"';
      c += kColumns[k];
      c += '"';
    }
    c += "],";
    text.endLine();
    text.line(
        "  \"joint_names\": [\"j1\", \"j2\", \"j3\", \"j4\", \"j5\", \"j6\", \"a1\", \"a2\"],");
    text.line("  \"points\": [");
  } else {
    std::string& c = text.buffer();
    for (std::size_t k = 0; k < std::size(kColumns); ++k) {
      if (k > 0) c += ',';
      c += kColumns[k];
    }
    text.endLine();
  }
  ExportResult result;
  result.format = format_;
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    std::string& b = text.buffer();
    if (json) b += "    [";
    appendRow(b, p, cell, ',', json);
    if (json) b += i + 1 < count ? "]," : "]";
    text.endLine();
    ++result.motionCount;
    if (p.pathStart) ++result.arcCount;
  }
  if (json) {
    text.line("  ]");
    text.line("}");
  }
  ExportFile file;
  file.name = makeProgramName(baseProgramName(cell, options), 64, false) +
              std::string(fileExtension(format_));
  file.lines = text.lineCount();
  file.text = text.take();
  result.files.push_back(std::move(file));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
