// Test helper shared by the export tests: axis speeds recomputed from a motion's CSV export, as a
// process engineer would check them, independently of the planner's time parameterisation.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "curvedslicer/export/exporter.hpp"
#include "export_test_support.hpp"

namespace curvedslicer::testing {

/// Reads the CSV export of `motion` and checks, move by move, |Δangle| / Δt of the six robot joints
/// and the two positioner axes against the cell's speed limits (the CSV writes shortest
/// round-trip numbers; the only rounding is that of the absolute times, allowed for below).
inline void expectAxisSpeedsFromCsv(const MotionPlan& motion, const Cell& cell) {
  const ExportResult r = exportProgram(motion, cell, ExportFormat::Csv);
  ASSERT_EQ(r.files.size(), 1u);
  std::istringstream in(r.files[0].text);
  std::string line;
  ASSERT_TRUE(static_cast<bool>(std::getline(in, line)));
  std::map<std::string, std::size_t> column;
  {
    std::istringstream header(line);
    std::string name;
    for (std::size_t i = 0; std::getline(header, name, ','); ++i) column[name] = i;
  }
  const char* names[8] = {"j1_deg", "j2_deg", "j3_deg", "j4_deg",
                          "j5_deg", "j6_deg", "a1_deg", "a2_deg"};
  double limits[8];
  for (int j = 0; j < 6; ++j) limits[j] = cell.robot.joints[j].maxSpeed / kDegT;
  limits[6] = cell.positioner.tilt.limit.maxSpeed / kDegT;
  limits[7] = cell.positioner.rotation.limit.maxSpeed / kDegT;
  for (const char* name : names) ASSERT_TRUE(column.count(name)) << name;
  ASSERT_TRUE(column.count("time_s"));
  std::vector<double> previous;
  std::size_t rows = 0, failures = 0;
  double fastest = 0.0;  // of the limit
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    std::vector<double> now(9);
    for (int a = 0; a < 8; ++a) now[a] = std::stod(fields.at(column[names[a]]));
    now[8] = std::stod(fields.at(column["time_s"]));
    if (!previous.empty()) {
      // Δt from two absolute times: each carries up to half an ulp of the time itself, which
      // matters for moves of microseconds late in a program (the planned duration is exact).
      const double ulp = std::nextafter(now[8], kInf) - now[8];
      const double dt = now[8] - previous[8] + 2.0 * ulp;
      ASSERT_GE(dt, 0.0) << "row " << rows;
      for (int a = 0; a < 8; ++a) {
        const double change = std::abs(now[a] - previous[a]);
        const double used = dt > 0.0 ? change / dt / limits[a] : (change > 0.0 ? kInf : 0.0);
        fastest = std::max(fastest, used);
        if (used > 1.0 + 1e-9 && ++failures <= 5) {
          ADD_FAILURE() << names[a] << " at row " << rows << ": " << change << " deg in " << dt
                        << " s, limit " << limits[a] << " deg/s";
        }
      }
    }
    previous = now;
    ++rows;
  }
  EXPECT_EQ(rows, motion.points.size());
  EXPECT_EQ(failures, 0u);
  EXPECT_GT(fastest, 0.0);
}

}  // namespace curvedslicer::testing
