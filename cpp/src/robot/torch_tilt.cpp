// Collision avoidance by torch angle (robot/torch_tilt.hpp).
#include "torch_tilt.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "curvedslicer/robot/positioner.hpp"
#include "deposit_index.hpp"
#include "torch_checker.hpp"

namespace curvedslicer::detail {
namespace {

constexpr double kRingStep = 2.5 * std::numbers::pi / 180.0;  // rad, largest step between rings
constexpr int kDirections = 16;
constexpr int kRounds = 3;

/// The torch at a path point: tip, the body's direction along gravity (`up`, part frame) and
/// the travel direction orthogonal to it with its left-hand side.
struct TorchFrame {
  Vec3 tip = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  Vec3 along = Vec3::UnitX();
  Vec3 across = Vec3::UnitY();
};

/// The unit vector of `v` orthogonal to unit `n`, or zero when `v` is (nearly) along `n`.
Vec3 orthogonalUnit(const Vec3& v, const Vec3& n) {
  const Vec3 w = v - n * n.dot(v);
  const double norm = w.norm();
  return norm > 1e-9 ? Vec3(w / norm) : Vec3(Vec3::Zero());
}

/// `lean` made orthogonal to `up` with its length kept (a lean taken over from a neighbour).
Vec3 leanAt(const Vec3& lean, const Vec3& up) {
  const double angle = lean.norm();
  if (angle <= 0.0) return Vec3::Zero();
  return angle * orthogonalUnit(lean, up);
}

class TiltPass {
 public:
  TiltPass(MotionPlan& motion, const Cell& cell, const CollisionGeometry& geometry,
           const Vec3& gravity, double beadRadius, double maxAngle, double fallbackAngle)
      : motion_(motion),
        cell_(cell),
        gravity_(gravity),
        maxAngle_(maxAngle),
        fallbackAngle_(std::clamp(fallbackAngle, 0.0, maxAngle)),
        rings_(std::max(1, static_cast<int>(std::ceil(maxAngle / kRingStep - 1e-9)))),
        deposit_(bounds(motion), beadRadius, 2.0 * (geometry.torch.radius + beadRadius)),
        checker_(cell, geometry, deposit_) {}

  /// Torch angles taken over from `earlier` (a pass over the same plan) for every path whose
  /// points and positioner angles are the same there: its search would find the same leans.
  void reuse(const MotionPlan* earlier) { earlier_ = earlier; }

  TorchTiltSummary run(const Progress& progress) {
    progress.report(0.0, "torch angles");
    for (std::size_t s = 0; s < motion_.paths.size(); ++s) {
      if (takeOver(s)) {
        progress.report(static_cast<double>(s + 1) / static_cast<double>(motion_.paths.size()),
                        "torch angles");
        continue;
      }
      planPath(motion_.paths[s]);
      progress.report(static_cast<double>(s + 1) / static_cast<double>(motion_.paths.size()),
                      "torch angles");
    }
    deposit_.setVisible(static_cast<std::size_t>(-1));
    return summary_;
  }

 private:
  static Aabb bounds(const MotionPlan& motion) {
    Aabb box;
    for (const MotionPoint& m : motion.points) box.extend(m.position);
    if (box.empty()) box.extend(Vec3::Zero());
    return box;
  }

  TorchFrame frameAt(std::size_t k, const MotionPathSpan& span) const {
    const MotionPoint& m = motion_.points[k];
    TorchFrame f;
    f.tip = m.position;
    const Mat3 partInWorld = computePartInWorld(cell_.positioner, m.a1, m.a2).linear();
    f.up = -(partInWorld.transpose() * gravity_).normalized();
    const Vec3 next = k + 1 < span.end ? motion_.points[k + 1].position : m.position;
    const Vec3 prev = k > span.begin ? motion_.points[k - 1].position : m.position;
    f.along = orthogonalUnit(next - prev, f.up);
    if (f.along.isZero()) f.along = orthogonalUnit(Vec3::UnitX(), f.up);
    if (f.along.isZero()) f.along = orthogonalUnit(Vec3::UnitY(), f.up);
    f.across = f.up.cross(f.along);
    return f;
  }

  bool collides(const TorchFrame& f, const Vec3& lean) const {
    return checker_.collidesWithWrist(f.tip, tiltedTorchUp(f.up, lean));
  }

  /// Direction j of a ring: unit, orthogonal to the torch axis.
  static Vec3 direction(const TorchFrame& f, int j) {
    const double phi = 2.0 * std::numbers::pi * j / kDirections;
    return std::cos(phi) * f.along + std::sin(phi) * f.across;
  }

  double ringAngle(int ring) const { return maxAngle_ * ring / rings_; }

  /// The middle of the longest run of clearing directions of a ring (the one farthest from
  /// what the torch hits), -1 when none clears.
  static int middleOfClearRun(const std::array<bool, kDirections>& clear) {
    int best = -1, bestRun = 0;
    for (int j = 0; j < kDirections; ++j) {
      if (!clear[j] || clear[(j + kDirections - 1) % kDirections]) continue;  // run starts
      int run = 0;
      while (run < kDirections && clear[(j + run) % kDirections]) ++run;
      if (run > bestRun) bestRun = run, best = (j + run / 2) % kDirections;
    }
    if (best < 0 && clear[0]) best = 0;  // every direction clears
    return best;
  }

  /// The clearing direction of ring `angle` to take: the one nearest `want` (unit, or zero)
  /// when given, tried in that order; else the middle of the longest clearing run. -1: none.
  int clearingDirection(const TorchFrame& f, double angle, const Vec3& want) const {
    if (want.isZero()) {
      std::array<bool, kDirections> clear{};
      for (int j = 0; j < kDirections; ++j) clear[j] = !collides(f, angle * direction(f, j));
      return middleOfClearRun(clear);
    }
    std::array<std::pair<double, int>, kDirections> order;
    for (int j = 0; j < kDirections; ++j) order[j] = {-direction(f, j).dot(want), j};
    std::sort(order.begin(), order.end());
    for (const auto& [key, j] : order) {
      if (!collides(f, angle * direction(f, j))) return j;
    }
    return -1;
  }

  /// The smallest lean that clears the torch at `f` (see the file comment); `cleared` false
  /// (and no lean) when none at the window's angle does.
  Vec3 search(const TorchFrame& f, const Vec3& preferred, bool& cleared) const {
    Vec3 want = preferred.isZero() ? Vec3(Vec3::Zero()) : orthogonalUnit(preferred, f.up);
    // the window's ring first: where nothing clears there, smaller tilts are not tried (but the
    // fallback window's ring, where it is smaller: leaning further may meet something else);
    // its clearing direction guides the smaller rings (tried nearest it first) when nothing
    // else does
    double top = maxAngle_;
    int widest = clearingDirection(f, top, want);
    if (widest < 0 && fallbackAngle_ > 0.0 && fallbackAngle_ < maxAngle_) {
      top = fallbackAngle_;
      widest = clearingDirection(f, top, want);
    }
    cleared = widest >= 0;
    if (!cleared) return Vec3::Zero();
    if (want.isZero()) want = direction(f, widest);
    const int last =
        std::clamp(static_cast<int>(std::ceil(top / maxAngle_ * rings_ - 1e-9)), 1, rings_);
    for (int ring = 1; ring <= last; ++ring) {
      const int j = ring < last ? clearingDirection(f, ringAngle(ring), want) : widest;
      if (j < 0) continue;
      const Vec3 d = direction(f, j);
      double lo = ringAngle(ring - 1), hi = ring < last ? ringAngle(ring) : top;
      for (int halving = 0; halving < 2; ++halving) {
        const double mid = 0.5 * (lo + hi);
        (collides(f, mid * d) ? lo : hi) = mid;
      }
      return hi * d;
    }
    return Vec3::Zero();  // not reached: the widest ring clears
  }

  void planPath(const MotionPathSpan& span);
  bool takeOver(std::size_t s);
  void addPathDeposit(const MotionPathSpan& span, std::vector<std::size_t>* visible);
  std::vector<Vec3> spread(const MotionPathSpan& span, const std::vector<TorchFrame>& frames,
                           const std::vector<Vec3>& need) const;
  void record(std::size_t k, const TorchFrame& f, const Vec3& lean);

  MotionPlan& motion_;
  const Cell& cell_;
  const Vec3 gravity_;
  const double maxAngle_;
  const double fallbackAngle_;
  const int rings_;
  DepositIndex deposit_;
  TorchChecker checker_;
  TorchTiltSummary summary_;
  const MotionPlan* earlier_ = nullptr;
};

/// Adds the welded segments of a path to the deposit; `visible` (optional) gets, per point,
/// how many segments it sees (those before it).
void TiltPass::addPathDeposit(const MotionPathSpan& span, std::vector<std::size_t>* visible) {
  bool first = true;
  for (std::size_t k = span.begin; k < span.end; ++k) {
    if (visible != nullptr) (*visible)[k - span.begin] = deposit_.segments().size();
    const MotionPoint& m = motion_.points[k];
    if (k > span.begin && m.arcOn) {
      deposit_.add({motion_.points[k - 1].position, m.position, m.layer, m.path}, first);
      first = false;
    }
  }
}

bool TiltPass::takeOver(std::size_t s) {
  if (earlier_ == nullptr || s >= earlier_->paths.size()) return false;
  const MotionPathSpan& span = motion_.paths[s];
  const MotionPathSpan& old = earlier_->paths[s];
  if (old.layer != span.layer || old.path != span.path ||
      old.end - old.begin != span.end - span.begin) {
    return false;
  }
  constexpr std::uint32_t kPositionerFlags = kMotionGravityDeviated | kMotionInserted;
  for (std::size_t i = 0; i < span.end - span.begin; ++i) {
    const MotionPoint& a = motion_.points[span.begin + i];
    const MotionPoint& b = earlier_->points[old.begin + i];
    if (a.a1 != b.a1 || a.a2 != b.a2 || a.position != b.position ||
        (a.flags & kPositionerFlags) != (b.flags & kPositionerFlags) ||
        b.torchAngle > maxAngle_ + 1e-12) {  // a lean beyond this pass's window is searched
      return false;
    }
  }
  addPathDeposit(span, nullptr);
  for (std::size_t i = 0; i < span.end - span.begin; ++i) {
    const MotionPoint& b = earlier_->points[old.begin + i];
    const double angle = b.torchAngle;
    MotionPoint& m = motion_.points[span.begin + i];
    m.torchLean = b.torchLean;
    m.torchAngle = angle;
    m.travelAngle = b.travelAngle;
    m.workAngle = b.workAngle;
    m.flags = (m.flags & ~static_cast<std::uint32_t>(kMotionTorchTilted)) |
              (b.flags & kMotionTorchTilted);
    if (angle > 0.0) {
      ++summary_.tilted;
      summary_.maxAngle = std::max(summary_.maxAngle, angle);
    }
  }
  return true;
}

/// Each lean spreads to the path's neighbours, shrinking by kTiltRate per mm of path: a point
/// that needs a lean of its own keeps it (it was searched so that it clears there), any other
/// takes the longest of the spread ones (turned orthogonal to its torch axis).
std::vector<Vec3> TiltPass::spread(const MotionPathSpan& span,
                                   const std::vector<TorchFrame>& frames,
                                   const std::vector<Vec3>& need) const {
  const std::size_t n = span.end - span.begin;
  std::vector<double> s(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    s[k] = s[k - 1] +
           (motion_.points[span.begin + k].position - motion_.points[span.begin + k - 1].position)
               .norm();
  }
  std::vector<Vec3> lean = need;
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = need[i].norm();
    if (angle <= 0.0) continue;
    const auto offer = [&](std::size_t j) {
      const double reduced = angle - kTiltRate * std::abs(s[j] - s[i]);
      if (reduced <= 0.0) return false;
      if (need[j].isZero() && reduced > lean[j].norm()) {
        lean[j] = leanAt(need[i] * (reduced / angle), frames[j].up);
      }
      return true;
    };
    for (std::size_t j = i + 1; j < n && offer(j); ++j) {
    }
    for (std::size_t j = i; j-- > 0 && offer(j);) {
    }
  }
  return lean;
}

void TiltPass::record(std::size_t k, const TorchFrame& f, const Vec3& lean) {
  MotionPoint& m = motion_.points[k];
  m.torchLean = lean;
  m.torchAngle = lean.norm();
  m.travelAngle = m.workAngle = 0.0;
  m.flags &= ~static_cast<std::uint32_t>(kMotionTorchTilted);
  if (m.torchAngle <= 0.0) return;
  const Vec3 up = tiltedTorchUp(f.up, lean);
  m.travelAngle = std::atan2(-up.dot(f.along), up.dot(f.up));
  m.workAngle = std::atan2(up.dot(f.across), up.dot(f.up));
  m.flags |= kMotionTorchTilted;
  ++summary_.tilted;
  summary_.maxAngle = std::max(summary_.maxAngle, m.torchAngle);
}

void TiltPass::planPath(const MotionPathSpan& span) {
  // the whole path's segments go into the deposit now; each point sees those before it
  std::vector<std::size_t> visible(span.end - span.begin);
  addPathDeposit(span, &visible);
  std::vector<TorchFrame> frames;
  frames.reserve(span.end - span.begin);
  for (std::size_t k = span.begin; k < span.end; ++k) frames.push_back(frameAt(k, span));
  std::vector<Vec3> need(span.end - span.begin, Vec3::Zero());
  std::vector<bool> failed(need.size(), false);
  Vec3 previous = Vec3::Zero();
  for (std::size_t i = 0; i < need.size(); ++i) {
    deposit_.setVisible(visible[i]);
    if (maxAngle_ > 0.0 && collides(frames[i], Vec3::Zero())) {
      bool cleared = false;
      need[i] = search(frames[i], previous, cleared);
      failed[i] = !cleared;
    }
    previous = need[i];
  }
  std::vector<Vec3> lean = spread(span, frames, need);
  for (int round = 0; round < kRounds; ++round) {
    bool changed = false;
    for (std::size_t i = 0; i < need.size(); ++i) {
      if (failed[i] || (lean[i] - need[i]).norm() < 1e-12) continue;  // checked as it is
      deposit_.setVisible(visible[i]);
      if (!collides(frames[i], lean[i])) continue;
      bool cleared = false;
      need[i] = search(frames[i], lean[i], cleared);
      failed[i] = !cleared;
      changed = true;
    }
    if (!changed) break;
    lean = spread(span, frames, need);
  }
  for (std::size_t i = 0; i < need.size(); ++i) {
    record(span.begin + i, frames[i], lean[i]);
    if (failed[i]) ++summary_.uncleared;
  }
}

}  // namespace

TorchTiltSummary planTorchTilts(MotionPlan& motion, const Cell& cell,
                                const CollisionGeometry& geometry, const Vec3& gravity,
                                double beadRadius, double maxAngle, const Progress& progress,
                                double fallbackAngle, const MotionPlan* earlier) {
  TiltPass pass(motion, cell, geometry, gravity, beadRadius, maxAngle, fallbackAngle);
  pass.reuse(earlier);
  return pass.run(progress);
}

}  // namespace curvedslicer::detail
