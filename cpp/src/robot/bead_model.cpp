#include "curvedslicer/robot/bead_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

std::string formatValue(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

[[noreturn]] void failField(const std::string& key, const std::string& problem,
                            const std::string& value, const std::string& hint) {
  throw InvalidInput("field /process/bead_model/" + key + " " + problem + ": " + value + "; " +
                     hint);
}

void checkAxis(const std::vector<double>& axis, const std::string& key) {
  if (axis.size() < 2) {
    failField(key, "needs at least 2 values", std::to_string(axis.size()),
              "measure the beads at two or more settings");
  }
  for (std::size_t i = 0; i < axis.size(); ++i) {
    if (!std::isfinite(axis[i]) || !(axis[i] > 0.0)) {
      failField(key, "must hold positive numbers", formatValue(axis[i]), "give them in order");
    }
    if (i > 0 && !(axis[i] > axis[i - 1])) {
      failField(key, "must be strictly ascending",
                formatValue(axis[i - 1]) + " then " + formatValue(axis[i]), "sort the grid");
    }
  }
}

void checkTable(const std::vector<std::vector<double>>& table, const std::string& key,
                std::size_t rows, std::size_t columns) {
  if (table.size() != rows) {
    failField(key,
              "has " + std::to_string(table.size()) + " rows, expected " + std::to_string(rows),
              std::to_string(table.size()), "give one row per entry of wire_feed_m_min");
  }
  for (std::size_t r = 0; r < rows; ++r) {
    const std::string row = key + "/" + std::to_string(r);
    if (table[r].size() != columns) {
      failField(
          row,
          "has " + std::to_string(table[r].size()) + " values, expected " + std::to_string(columns),
          std::to_string(table[r].size()), "give one value per entry of travel_speed_mm_s");
    }
    for (const double v : table[r]) {
      if (!std::isfinite(v) || !(v > 0.0)) {
        failField(row, "must hold positive numbers of mm", formatValue(v),
                  "give the measured bead size");
      }
    }
  }
}

/// Index of the cell along an axis holding x (clamped to the table) and the fraction in it.
std::pair<std::size_t, double> locate(const std::vector<double>& axis, double x) {
  const double clamped = std::clamp(x, axis.front(), axis.back());
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), clamped) - axis.begin());
  i = std::clamp<std::size_t>(i, 1, axis.size() - 1) - 1;
  return {i, (clamped - axis[i]) / (axis[i + 1] - axis[i])};
}

double bilinear(const std::vector<std::vector<double>>& t, std::size_t i, std::size_t j, double u,
                double v) {
  return (1 - u) * (1 - v) * t[i][j] + u * (1 - v) * t[i + 1][j] + (1 - u) * v * t[i][j + 1] +
         u * v * t[i + 1][j + 1];
}

/// Newton's method on the bilinear system from (u, v), kept in [0, 1]²; returns the relative
/// squared error at the best point found (left in u, v).
template <typename Cost>
double newtonInCell(const std::vector<std::vector<double>>& W,
                    const std::vector<std::vector<double>>& H, std::size_t i, std::size_t j,
                    double width, double height, const Cost& cost, double& u, double& v) {
  double best = cost(u, v);
  for (int iteration = 0; iteration < 40 && best > 1e-24; ++iteration) {
    const double rw = bilinear(W, i, j, u, v) - width, rh = bilinear(H, i, j, u, v) - height;
    // Partial derivatives of the bilinear forms.
    const double wu = (1 - v) * (W[i + 1][j] - W[i][j]) + v * (W[i + 1][j + 1] - W[i][j + 1]);
    const double wv = (1 - u) * (W[i][j + 1] - W[i][j]) + u * (W[i + 1][j + 1] - W[i + 1][j]);
    const double hu = (1 - v) * (H[i + 1][j] - H[i][j]) + v * (H[i + 1][j + 1] - H[i][j + 1]);
    const double hv = (1 - u) * (H[i][j + 1] - H[i][j]) + u * (H[i + 1][j + 1] - H[i + 1][j]);
    const double det = wu * hv - wv * hu;
    if (!(std::abs(det) > 1e-300)) break;
    const double nu = std::clamp(u - (hv * rw - wv * rh) / det, 0.0, 1.0);
    const double nv = std::clamp(v - (-hu * rw + wu * rh) / det, 0.0, 1.0);
    const double c = cost(nu, nv);
    if (!(c < best)) {
      // A clamped step that does not improve: try half of it once, then stop.
      const double hu2 = 0.5 * (u + nu), hv2 = 0.5 * (v + nv);
      const double c2 = cost(hu2, hv2);
      if (!(c2 < best)) break;
      u = hu2;
      v = hv2;
      best = c2;
      continue;
    }
    u = nu;
    v = nv;
    best = c;
  }
  return best;
}

/// The point of cell (i, j) whose (width, height) is nearest to the wanted pair in relative
/// squared error: Newton inside, closed-form least squares on each edge. Returns the error and
/// leaves the point in (u, v).
double solveInCell(const BeadModel& m, std::size_t i, std::size_t j, double width, double height,
                   double& u, double& v) {
  const auto& W = m.width;
  const auto& H = m.height;
  const auto cost = [&](double a, double b) {
    const double dw = (bilinear(W, i, j, a, b) - width) / width;
    const double dh = (bilinear(H, i, j, a, b) - height) / height;
    return dw * dw + dh * dh;
  };
  // Out of reach inside the cell the least error lies on its boundary: the best point of every
  // edge (width and height are linear along an edge: least squares in closed form).
  const std::array<std::array<double, 4>, 4> edges = {
      {{0, 0, 1, 0}, {0, 1, 1, 1}, {0, 0, 0, 1}, {1, 0, 1, 1}}};  // (u0, v0) → (u1, v1)
  double best = std::numeric_limits<double>::infinity();
  for (const auto& e : edges) {
    const double w0 = bilinear(W, i, j, e[0], e[1]), w1 = bilinear(W, i, j, e[2], e[3]);
    const double h0 = bilinear(H, i, j, e[0], e[1]), h1 = bilinear(H, i, j, e[2], e[3]);
    const double a = (w0 - width) / width, b = (w1 - w0) / width;
    const double c = (h0 - height) / height, d = (h1 - h0) / height;
    const double tau =
        b * b + d * d > 0.0 ? std::clamp(-(a * b + c * d) / (b * b + d * d), 0.0, 1.0) : 0.0;
    const double eu = e[0] + tau * (e[2] - e[0]), ev = e[1] + tau * (e[3] - e[1]);
    const double ce = cost(eu, ev);
    if (ce < best) {
      best = ce;
      u = eu;
      v = ev;
    }
  }
  // Inside: Newton's method from the cell's centre.
  double nu0 = 0.5, nv0 = 0.5;
  const double newton = newtonInCell(W, H, i, j, width, height, cost, nu0, nv0);
  if (newton < best) {
    best = newton;
    u = nu0;
    v = nv0;
  }
  return best;
}

}  // namespace

void validateBeadModel(const BeadModel& m) {
  checkAxis(m.wireFeeds, "wire_feed_m_min");
  checkAxis(m.travelSpeeds, "travel_speed_mm_s");
  checkTable(m.width, "width_mm", m.wireFeeds.size(), m.travelSpeeds.size());
  checkTable(m.height, "height_mm", m.wireFeeds.size(), m.travelSpeeds.size());
}

BeadGeometry evaluateBeadModel(const BeadModel& m, double wireFeed, double travelSpeed) {
  const auto [i, u] = locate(m.wireFeeds, wireFeed);
  const auto [j, v] = locate(m.travelSpeeds, travelSpeed);
  return {bilinear(m.width, i, j, u, v), bilinear(m.height, i, j, u, v)};
}

BeadSetting solveBeadSetting(const BeadModel& m, double width, double height, double tolerance) {
  if (!std::isfinite(width) || !(width > 0.0) || !std::isfinite(height) || !(height > 0.0)) {
    throw InvalidInput("bead size to reach must be positive: width " + formatValue(width) +
                       " mm, height " + formatValue(height) +
                       " mm; pass the plan's bead width and layer thickness");
  }
  BeadSetting best;
  double bestCost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < m.wireFeeds.size(); ++i) {
    for (std::size_t j = 0; j + 1 < m.travelSpeeds.size(); ++j) {
      double u = 0.0, v = 0.0;
      const double c = solveInCell(m, i, j, width, height, u, v);
      if (c < bestCost) {
        bestCost = c;
        best.wireFeed = m.wireFeeds[i] + u * (m.wireFeeds[i + 1] - m.wireFeeds[i]);
        best.travelSpeed = m.travelSpeeds[j] + v * (m.travelSpeeds[j + 1] - m.travelSpeeds[j]);
      }
    }
  }
  best.achieved = evaluateBeadModel(m, best.wireFeed, best.travelSpeed);
  best.reached = std::abs(best.achieved.width - width) <= tolerance &&
                 std::abs(best.achieved.height - height) <= tolerance;
  return best;
}

}  // namespace curvedslicer
