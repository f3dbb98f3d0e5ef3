// Format registry, joint-limit check and the all-or-nothing file writer (see exporter.hpp).
#include "curvedslicer/export/exporter.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <system_error>

#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/gcode_writer.hpp"
#include "curvedslicer/export/jbi_writer.hpp"
#include "curvedslicer/export/krl_writer.hpp"
#include "curvedslicer/export/ls_writer.hpp"
#include "curvedslicer/export/neutral_writer.hpp"
#include "curvedslicer/export/rapid_writer.hpp"
#include "curvedslicer/voxel/voxelize.hpp"  // physicalMemoryBytes
#include "writer_support.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;
using export_detail::kRadToDeg;

const std::vector<ExportFormatInfo>& exportFormats() {
  static const std::vector<ExportFormatInfo> formats = {
      {ExportFormat::Jbi, "jbi", ".JBI", "Yaskawa INFORM"},
      {ExportFormat::Krl, "krl", ".src", "KUKA KRL"},
      {ExportFormat::Rapid, "rapid", ".mod", "ABB RAPID"},
      {ExportFormat::Ls, "ls", ".LS", "Fanuc LS"},
      {ExportFormat::Gcode, "gcode", ".ngc", "G-code for a tilt-rotate table"},
      {ExportFormat::Csv, "csv", ".csv", "neutral CSV"},
      {ExportFormat::Json, "json", ".json", "neutral JSON"},
  };
  return formats;
}

namespace {

const ExportFormatInfo& infoOf(ExportFormat format) {
  for (const ExportFormatInfo& info : exportFormats()) {
    if (info.format == format) return info;
  }
  return exportFormats().front();
}

}  // namespace

std::string_view toString(ExportFormat format) {
  return infoOf(format).name;
}

ExportFormat parseExportFormat(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::string names;
  for (const ExportFormatInfo& info : exportFormats()) {
    if (lower == info.name) return info.format;
    names += (names.empty() ? "" : ", ") + std::string(info.name);
  }
  throw InvalidInput("unknown export format: '" + std::string(name) + "'; use one of " + names);
}

std::string_view toString(GcodeMode mode) {
  return mode == GcodeMode::Machine ? "machine" : "tcp";
}

GcodeMode parseGcodeMode(std::string_view name) {
  if (name == "tcp") return GcodeMode::Tcp;
  if (name == "machine") return GcodeMode::Machine;
  throw InvalidInput("unknown G-code mode: '" + std::string(name) + "'; use tcp or machine");
}

std::string_view toString(GcodeDialect dialect) {
  return dialect == GcodeDialect::LinuxCnc ? "linuxcnc" : "generic";
}

GcodeDialect parseGcodeDialect(std::string_view name) {
  if (name == "generic") return GcodeDialect::Generic;
  if (name == "linuxcnc") return GcodeDialect::LinuxCnc;
  throw InvalidInput("unknown G-code dialect: '" + std::string(name) +
                     "'; use generic or linuxcnc");
}

std::string_view fileExtension(ExportFormat format) {
  return infoOf(format).extension;
}

std::unique_ptr<ProgramExporter> makeExporter(ExportFormat format) {
  switch (format) {
    case ExportFormat::Jbi:
      return std::make_unique<JbiWriter>();
    case ExportFormat::Krl:
      return std::make_unique<KrlWriter>();
    case ExportFormat::Rapid:
      return std::make_unique<RapidWriter>();
    case ExportFormat::Ls:
      return std::make_unique<LsWriter>();
    case ExportFormat::Gcode:
      return std::make_unique<GcodeWriter>();
    case ExportFormat::Csv:
      return std::make_unique<NeutralWriter>(ExportFormat::Csv);
    case ExportFormat::Json:
      return std::make_unique<NeutralWriter>(ExportFormat::Json);
  }
  throw InvalidInput("unknown export format; use one of jbi, krl, rapid, ls, gcode, csv, json");
}

namespace {

/// "YYYY/MM/DD HH:MM" with digits where the pattern has them.
bool isProgramDate(const std::string& date) {
  const std::string pattern = "dddd/dd/dd dd:dd";
  if (date.size() != pattern.size()) return false;
  for (std::size_t k = 0; k < pattern.size(); ++k) {
    const bool digit = std::isdigit(static_cast<unsigned char>(date[k])) != 0;
    if (pattern[k] == 'd' ? !digit : date[k] != pattern[k]) return false;
  }
  return true;
}

/// `text` for a message: control characters as \r, \n, \t or \xHH, cut after 40 characters.
std::string quoteForMessage(const std::string& text) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  for (std::size_t k = 0; k < text.size() && k < 40; ++k) {
    const auto c = static_cast<unsigned char>(text[k]);
    if (c == '\r') {
      out += "\\r";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      out += std::string("\\x") + kHex[c >> 4] + kHex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (text.size() > 40) out += "...";
  return out;
}

}  // namespace

void checkExportSize(std::size_t points, double memoryBudgetBytes) {
  double budget = memoryBudgetBytes;
  if (!(budget > 0.0)) {
    const double physical = physicalMemoryBytes();
    budget = physical > 0.0 ? 0.8 * physical : 4e9;  // as the voxel grid's budget
  }
  const double perPoint = static_cast<double>(sizeof(MotionPoint)) + kExportTextBytesPerPoint;
  const double bytes = static_cast<double>(points) * perPoint;
  if (!(bytes > budget)) return;
  char text[256];
  std::snprintf(text, sizeof(text),
                "the export of %zu plan points would need about %.1f GB (%.0f bytes per point: "
                "motion and program text), over the memory budget of %.1f GB",
                points, bytes / 1e9, perPoint, budget / 1e9);
  throw ResourceLimit(std::string(text) +
                      "; export fewer layers or re-plan with a larger point spacing");
}

void validateExportOptions(const ExportOptions& options) {
  if (!isProgramDate(options.date)) {
    throw InvalidInput("date must look like \"YYYY/MM/DD HH:MM\": '" +
                       quoteForMessage(options.date) + "'; e.g. \"2026/11/22 07:00\"");
  }
}

ExportResult exportProgram(const MotionPlan& motion, const Cell& cell, ExportFormat format,
                           const ExportOptions& options, const Progress& progress) {
  validateExportOptions(options);
  return makeExporter(format)->write(motion, cell, options, progress);
}

namespace {

[[noreturn]] void throwLimit(const MotionPoint& p, std::size_t i, const std::string& joint,
                             double angle, const JointLimit& limit) {
  const double beyond = angle < limit.min ? limit.min - angle : angle - limit.max;
  // Path points by their plan index; arc-off points (index -1) by their kind and the path.
  const std::string point = p.kind == MoveKind::Path ? "point " + std::to_string(p.index)
                                                     : std::string(toString(p.kind)) + " move";
  throw InvalidInput(
      "motion point " + std::to_string(i) + " (layer " + std::to_string(p.layer) + ", path " +
      std::to_string(p.path) + ", " + point + ") crosses the limit of " + joint + ": " +
      formatFixed(angle * kRadToDeg, 3) + " deg outside [" + formatFixed(limit.min * kRadToDeg, 3) +
      ", " + formatFixed(limit.max * kRadToDeg, 3) + "] deg by " +
      formatFixed(beyond * kRadToDeg, 3) +
      " deg; re-plan the motion for this cell, change the part's place on the table, or widen "
      "the limit in the cell if the machine allows it");
}

}  // namespace

void checkJointLimits(const MotionPlan& motion, const Cell& cell) {
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const MotionPoint& p = motion.points[i];
    for (int j = 0; j < 6; ++j) {
      if (!cell.robot.joints[j].contains(p.joints[j])) {
        throwLimit(p, i, "robot joint " + std::to_string(j + 1), p.joints[j], cell.robot.joints[j]);
      }
    }
    if (const JointInequality* limit = violatedInterference(cell.robot, p.joints)) {
      std::string joints;
      for (int j = 0; j < 6; ++j) {
        joints += (j ? ", " : "") + formatFixed(p.joints[j] * kRadToDeg, 3);
      }
      throw InvalidInput("motion point " + std::to_string(i) + " (layer " +
                         std::to_string(p.layer) + ", path " + std::to_string(p.path) +
                         ") violates the robot's interference limit " + limit->name +
                         " (robot/interference): joints " + joints +
                         " deg; re-plan the motion for this cell or change the part's place");
    }
    if (!cell.positioner.tilt.limit.contains(p.a1)) {
      throwLimit(p, i, "the positioner tilt (a1)", p.a1, cell.positioner.tilt.limit);
    }
    if (!cell.positioner.rotation.endless && !cell.positioner.rotation.limit.contains(p.a2)) {
      throwLimit(p, i, "the positioner rotation (a2)", p.a2, cell.positioner.rotation.limit);
    }
  }
}

std::string programNameForFile(const fs::path& mainFile, std::string_view requested) {
  if (!requested.empty()) return std::string(requested);
  return mainFile.stem().string();
}

namespace {

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

void checkMainFileName(const ExportResult& result, const fs::path& mainFile) {
  if (result.files.empty() || result.format == ExportFormat::Csv ||
      result.format == ExportFormat::Json) {
    return;
  }
  const fs::path written(result.files.front().name);
  const std::string program = written.stem().string();
  const std::string given = mainFile.stem().string();
  if (lowerCase(program) == lowerCase(given)) return;
  throw InvalidInput("the output file name does not agree with the program name inside it: '" +
                     quoteForMessage(mainFile.filename().string()) + "' holds the " +
                     std::string(toString(result.format)) + " program " + program +
                     " (the requested name cut to the format's rules); name the file " + program +
                     mainFile.extension().string() +
                     " or give --name / program_name the file's name");
}

void writeExportFiles(const ExportResult& result, const fs::path& mainFile) {
  if (result.files.empty()) {
    throw InvalidInput("nothing to write: the export has no files; export a non-empty plan");
  }
  const fs::path folder = mainFile.has_parent_path() ? mainFile.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw IoError("output folder does not exist: '" + folder.string() +
                  "'; create it or choose another output path");
  }
  std::vector<fs::path> targets{mainFile};
  std::set<std::string> names{mainFile.filename().string()};
  for (std::size_t k = 1; k < result.files.size(); ++k) {
    targets.push_back(folder / result.files[k].name);
    if (!names.insert(result.files[k].name).second) {
      throw InvalidInput("two output files would have the same name: '" + result.files[k].name +
                         "'; choose another output file name");
    }
  }
  for (fs::path& target : targets) {
    if (fs::is_directory(target, ec)) {
      throw IoError("an output file would replace a folder: '" + target.string() +
                    "'; choose another output file name");
    }
    target = resolveOutputPath(target);  // no devices, FIFOs or sockets; through symlinks
  }
  checkMainFileName(result, mainFile);
  std::vector<fs::path> temps;
  const auto removeTemps = [&temps]() noexcept {
    std::error_code ignored;
    for (const auto& t : temps) fs::remove(t, ignored);
  };
  try {
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const fs::path tmp = prepareTemporaryFor(targets[k]);
      temps.push_back(tmp);
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw IoError("cannot write '" + targets[k].string() + "' (through the temporary file '" +
                      tmp.filename().string() + "'): " + std::strerror(errno) +
                      "; check that the folder is writable");
      }
      const std::string& text = result.files[k].text;
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      out.flush();
      if (!out) {
        throw IoError("writing '" + targets[k].string() +
                      "' failed (disk full?); nothing was written");
      }
    }
    for (std::size_t k = 0; k < targets.size(); ++k) {
      fs::rename(temps[k], targets[k], ec);
      if (ec) {
        throw IoError("cannot move '" + temps[k].string() + "' to '" + targets[k].string() +
                      "': " + ec.message());
      }
    }
  } catch (...) {
    removeTemps();
    throw;
  }
}

}  // namespace curvedslicer
