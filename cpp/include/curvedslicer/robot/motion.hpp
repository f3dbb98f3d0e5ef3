// Motion planning for a plan in a cell: per path point the positioner angles that turn the
// deposition direction V onto gravity (paper §3.2, eq. 16), the world pose of the point through
// the positioner's forward kinematics, a vertical torch pose (tool z along gravity, tool x fixed
// in the world per path or along the travel direction), the robot joint angles from closed-form
// inverse kinematics, one robot configuration per weld, the time of every point against every
// axis's speed limit and the process estimates. This is what the exporters (export/) consume.
//
// Method (details in docs/METHODS.md, "Positioner and robot"):
//   1. optional smoothing of V along each path (Gaussian in arc length), bounded so that the
//      smoothed V stays within `maxSmoothingDeviation` of the original V; consecutive points
//      closer than `mergeTolerance` merged;
//   2. eq. 16 in closed form with both branches (positioner.hpp), the branch and unwrapping
//      nearest the previous point within joint limits; a2 then follows its exact value as
//      closely as a bounded rate allows inside a tube where the compensating tilt keeps V within
//      `nearSingularBand` (3°) of gravity — any a2 inside the band of that angle around the
//      rotation axis, a blend of the exact values on both sides as target there; points
//      inserted where a2 would step more than `maxA2Step`; where joint limits make gravity
//      alignment impossible, the feasible pose of least residual and a warning;
//   3. per point the TCP pose in world and in the robot base, inverse kinematics (up to 8
//      solutions), the IK branch of the path's first point kept along the path, joints
//      continuous along a path, the fixed tool x turned about the torch axis so joint 6 sits in
//      the middle of a quadrant away from ±180°, the weld's configuration with hysteresis
//      (configuration.hpp); the arc-off move to a path start may turn R or T by a full turn when
//      that keeps the path inside the joint limits; unreachable points and joint-limit crossings
//      are named (which point, by how much / which joint);
//   4. time parameterisation (timing.hpp): each move as slow as its slowest axis requires, the
//      weld speed reduced only there (MotionPlan::speedReductions), estimates from it.
// Preconditions: every path has >= 2 points, unit normals and deposition directions. Cost:
// O(points), a few microseconds per point (IK, solved twice per path, dominates).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/core/types.hpp"
#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "curvedslicer/robot/placement.hpp"

namespace curvedslicer {

/// Bits of MotionPoint::flags.
enum MotionFlag : std::uint32_t {
  kMotionSingular = 1u << 0,         ///< V inside the near-singular band (as kMotionNearSingular)
  kMotionTiltLimited = 1u << 1,      ///< a1 clamped to its limit: V not on gravity (see residual)
  kMotionRotationLimited = 1u << 2,  ///< a2 clamped to its limit
  kMotionA2RateLimited = 1u << 3,  ///< outside the band, a2 off its exact value (V within the band
                                   ///< angle of gravity): blended for a bounded a2 rate
  kMotionSmoothed = 1u << 4,       ///< V was smoothed (usedDeposition != deposition)
  kMotionConfigurationChange = 1u << 5,  ///< robot configuration differs from the path start
  kMotionWristSingular = 1u << 6,        ///< joint 5 near 0: joints 4/6 split kept continuous
  kMotionRobotLimit = 1u << 7,           ///< no IK solution within the robot's joint limits
  kMotionSpeedReduced = 1u << 8,   ///< weld speed lowered here so every axis keeps its speed limit
  kMotionInserted = 1u << 9,       ///< point inserted by the planner (fast positioner turn)
  kMotionNearSingular = 1u << 10,  ///< V inside the near-singular band (a2 blended, rate bounded)
  kMotionCollision = 1u << 11,     ///< the move arriving here collides (--allow-collisions)
  kMotionTorchTilted = 1u << 12,   ///< torch tilted off gravity to clear deposit, table, fixture
  kMotionGravityDeviated = 1u << 13,  ///< V turned off gravity (within the cell's gravity
                                      ///< deviation window) so that the torch clears
};

/// What a motion point is. Path points are the plan's points (welded except the path's first);
/// the others are arc-off points the planner adds: the retract from a path end along the layer
/// normal, travel points at the clearance height, the approach above the next path start, and
/// the cell's home pose at the start and end of the program.
enum class MoveKind { Path, Retract, Travel, Approach, Home };

/// "path" | "retract" | "travel" | "approach" | "home".
std::string_view toString(MoveKind kind);

/// One robot/positioner target. Points of a path follow each other; the first point of a path
/// is reached by an arc-off travel move, every further point by a welding move.
struct MotionPoint {
  MoveKind kind = MoveKind::Path;  ///< arc-off points other than Path have index == -1
  int layer = 0;                   ///< Plan::layers index
  int path = 0;                    ///< index of the path within the layer
  int index = 0;  ///< index of the point in the path; a closed path repeats point 0 at the end
                  ///< with index == points.size() (the closing weld move)
  Vec3 position = Vec3::Zero();          ///< mm, part frame
  Vec3 normal = Vec3::UnitZ();           ///< part frame, unit
  Vec3 deposition = -Vec3::UnitZ();      ///< V from the plan, part frame, unit
  Vec3 usedDeposition = -Vec3::UnitZ();  ///< V after optional smoothing (what a1/a2 align)
  double a1 = 0.0;  ///< rad, positioner tilt, model convention (PositionerAxis::sign for ctrl)
  double a2 = 0.0;  ///< rad, positioner rotation, unwrapped (may exceed ±π when endless)
  /// rad, robot joints, controller convention, continuous along a path (no 2π jumps); with
  /// UnreachablePolicy::Warn and no IK solution: the previous point's joints (flagged)
  JointVector joints{};
  int configuration = 0;  ///< IK branch bits: 1 = back (shoulder), 2 = elbow down, 4 = wrist flip
  Pose toolInWorld = Pose::Identity();      ///< TCP pose in world
  Pose toolInRobotBase = Pose::Identity();  ///< TCP pose in the robot base frame (Cartesian target)
  Pose toolInTable = Pose::Identity();      ///< TCP pose in the positioner table frame
  Pose toolInPart = Pose::Identity();       ///< TCP pose in the part frame
  double speed = 0.0;  ///< mm/s of the move arriving here: weld speed (relative to the part;
                       ///< lower where kMotionSpeedReduced) or travel speed for arc-off moves
  /// m/min wire feed of the weld move arriving here (from the cell's bead model for
  /// the point's bead width and the layer height, or the cell's fixed wire feed); 0 for arc-off.
  double wireFeed = 0.0;
  double beadWidth = 0.0;  ///< mm, the plan's bead width at the point (0 for arc-off points)
  /// mm/s, the weld speed planned for the move before the axis limits (the cell's, or
  /// the bead model's for the point's width); 0 = the cell's weld speed (arc-off moves).
  double nominalSpeed = 0.0;
  int weldSchedule = 0;    ///< controller weld condition/schedule number for the move; 0 = cell's
  double time = 0.0;       ///< s from the program start to the arrival here (time parameterisation
                           ///< against every axis's speed limit; dwells included)
  bool arcOn = false;      ///< the move arriving at this point is welded
  bool pathStart = false;  ///< first point of a path (ARCON after reaching it)
  bool pathEnd = false;    ///< last point of a path (ARCOF after reaching it)
  double residual = 0.0;   ///< rad, angle between the transformed plan V and gravity: the
                           ///< gravity deviation of the deposit at this point
  /// Torch lean (part frame, orthogonal to the torch axis along gravity, norm = the torch
  /// angle in rad): the direction the torch body leans to where the torch is tilted off
  /// gravity to clear the deposit, the table or the fixture; zero where it runs along gravity.
  Vec3 torchLean = Vec3::Zero();
  /// rad, angle of the torch axis from gravity (|torchLean|; arc-off points: of their pose)
  double torchAngle = 0.0;
  /// rad, path points: the torch angle's share along the travel (projected onto the plane of
  /// gravity and the travel direction): > 0 push (tip ahead), < 0 drag; 0 on arc-off points
  double travelAngle = 0.0;
  double workAngle = 0.0;   ///< rad, its share across the travel: > 0 the body leans left
  std::uint32_t flags = 0;  ///< MotionFlag bits
};

/// Where a path lies in MotionPlan::points.
struct MotionPathSpan {
  int layer = 0;
  int path = 0;
  std::size_t begin = 0;  ///< first point
  std::size_t end = 0;    ///< one past the last point
  /// The robot configuration of the whole weld (constant within it; exporters write this).
  RobotConfiguration configuration;
};

/// A stretch of a path where the weld speed had to drop below the cell's weld speed.
struct SpeedReduction {
  int layer = 0;
  int path = 0;
  int firstIndex = 0;     ///< path point index where the reduction starts
  int lastIndex = 0;      ///< path point index where it ends
  double minSpeed = 0.0;  ///< mm/s, lowest weld speed in the stretch
  std::string axis;       ///< the limiting axis, e.g. "positioner rotation (a2)" or "robot T"
};

/// What a colliding torch hits.
enum class CollisionObstacle { Deposit, Table, Riser, Substrate, PositionerBody };

/// A move that still collides after raising/re-routing (error unless allowCollisions).
struct CollisionReport {
  std::size_t point = 0;  ///< MotionPlan::points index of the move's end point
  std::string what;       ///< e.g. "torch vs deposit of layer 5 path 2"
  double depth = 0.0;     ///< mm, penetration (or clearance deficit for travel moves)
  CollisionObstacle obstacle = CollisionObstacle::Deposit;
};

/// Process estimates (paper §4.1 process parameters from the cell).
struct MotionEstimate {
  double beadLength = 0.0;    ///< mm, arc-on length
  double arcTime = 0.0;       ///< s, beadLength / weld speed
  double travelLength = 0.0;  ///< mm, arc-off moves between paths (straight, part frame)
  double travelTime = 0.0;    ///< s, arc-off moves (the slower of robot and positioner)
  double dwellTime = 0.0;     ///< s, path and layer dwells (with coolingWait)
  /// s, of dwellTime: the waits after layers shorter than the cell's minimum layer time
  double coolingWait = 0.0;
  std::size_t cooledLayers = 0;  ///< layers that wait for the minimum layer time
  double totalTime = 0.0;        ///< s, arc + travel + dwell
  double wireLength = 0.0;       ///< mm, wire feed · arc time
  double depositedVolume = 0.0;  ///< mm³, wire cross-section · wire length · efficiency
  double depositedMass = 0.0;    ///< g
  std::size_t paths = 0;
  std::size_t points = 0;
  double maxTorchAngle = 0.0;        ///< rad, largest torch angle off gravity (planMotion)
  double maxGravityDeviation = 0.0;  ///< rad, largest residual of V from gravity (planMotion)
};

enum class UnreachablePolicy {
  Throw,  ///< InvalidInput naming the first unreachable points and by how much (default)
  Warn,   ///< keep the closest pose, flag kMotionRobotLimit and add a warning
};

/// "throw" | "warn" (the Python module's names).
std::string_view toString(UnreachablePolicy policy);
/// @throws InvalidInput naming the text and the choices.
UnreachablePolicy parseUnreachablePolicy(std::string_view name);

struct MotionOptions {
  /// rad (3°): the near-singular band and the stated gravity tolerance. V within this angle of
  /// the rotation axis: a2 is blended between its exact values on both sides (rate bounded, see
  /// docs/METHODS.md) and the tilt compensates, so V is within this angle of gravity anyway;
  /// outside the band a2 may leave its exact value only as far as the compensating tilt keeps V
  /// within this angle of gravity. Replaces the former singularZone / maxSingularA2Step.
  double nearSingularBand = 0.0523598775598299;
  double initialA2 = 0.0;          ///< rad, a2 held when the first points of the plan are singular
  bool preferPositiveTilt = true;  ///< branch at the first point: a1 >= 0 if feasible
  double smoothingLength = 0.0;    ///< mm, Gaussian sigma along the path for V; 0 = no smoothing
  double maxSmoothingDeviation = 0.0872664625997165;  ///< rad (5°), smoothed V vs plan V
  /// Tool x along the travel direction; off (default) keeps the torch orientation fixed in the
  /// world while the positioner turns the part: a round GMA torch does not care, and following
  /// the travel winds the wrist a full turn per ring (joint 6 past its limits).
  bool toolAlongTravel = false;
  UnreachablePolicy unreachable = UnreachablePolicy::Throw;
  double residualWarning = 0.0174532925199433;  ///< rad (1°): warn above this residual
  // ---- motion a cell can run (travel, collisions, speed limits, placement) ----
  double clearance = 10.0;       ///< mm, travel height above part and deposit (arc-off moves)
  bool allowCollisions = false;  ///< remaining collisions are warnings instead of errors
  bool addHome = true;           ///< start and end the program at the cell's home pose
  /// mm, consecutive path points closer than this are merged (the first kept; an open path
  /// keeps its last point); MotionPoint::index still names the plan point
  double mergeTolerance = 0.01;
  /// rad (5°): within a path a2 never steps more than this between consecutive points; points
  /// are inserted on the straight segment (kMotionInserted, index = the plan point before)
  double maxA2Step = 0.0872664625997165;
  bool timeParameterise = true;  ///< respect every axis's max speed (else nominal speeds only)
  /// Where the part sits on the table (placement.hpp): Rest (default) lifts the cell's
  /// table_to_part so the lowest bead bottom lies on the fixture's top (the table top without
  /// one; a start surface facing more than 30° from down turned onto the table first); Cell
  /// keeps it as given; Auto rests it on the lowest riser that keeps the torch clear of the
  /// table on every move (planMotion). Either way a weld point below the fixture's top or
  /// outside the working volume is InvalidInput.
  PartPlacement placement = PartPlacement::Rest;
};

struct MotionPlan {
  std::vector<MotionPoint> points;     ///< in execution order
  std::vector<MotionPathSpan> paths;   ///< in execution order
  std::vector<MotionEstimate> layers;  ///< per Plan layer
  MotionEstimate total;
  std::vector<std::string> warnings;            ///< aggregated, readable, at most a few per cause
  double maxResidual = 0.0;                     ///< rad, over points outside the near-singular band
  std::size_t singularPoints = 0;               ///< points inside the near-singular band
  std::size_t limitedPoints = 0;                ///< points with a positioner limit active
  std::vector<SpeedReduction> speedReductions;  ///< where the weld speed drops, and by how much
  std::vector<CollisionReport> collisions;      ///< what remains (only with allowCollisions)
  double nearSingularBand = 0.0;        ///< rad, V this close to the rotation axis is blended
  Pose tableToPart = Pose::Identity();  ///< the part placement used (after the placement rule)
  FixtureGeometry fixture;              ///< the riser and plate used (Auto: the riser it chose)
  /// e.g. defaults taken for an older cell version (Cell::notes), the placement rest made
  std::vector<std::string> notes;
};

/// Plans positioner angles, robot joints and estimates for every point of `plan` in `cell`.
/// Throws InvalidInput for an invalid cell or plan (names the layer/path/point) and, with
/// UnreachablePolicy::Throw, for points the robot cannot reach (which point, by how much);
/// Cancelled when `progress` asks. Deterministic.
/// PartPlacement::Auto plans with Rest on the cell's riser (height 0 without one; diameter: the
/// cell's, else the plate's side, else the first layer's footprint) and, while the torch
/// reaches into the table, raises the riser by the deepest reach plus 2 mm and plans again (at
/// most 12 times); a riser it chose itself (the cell gives no riser diameter) that the torch
/// reaches into is narrowed by twice the deepest reach plus 2 mm, down to a quarter of its first
/// width and, without a substrate plate, never below the first layer's beads laid on its top
/// (supportDiameterFor: a part on a raised start surface, a mandrel, may overhang it). The note
/// names the riser chosen. A torch that hits the cell's own riser or plate, or a riser that
/// cannot be narrowed further, is not cleared so: InvalidInput names the move and what would
/// help (a smaller riser or plate, a plate carrying the part on a narrower riser, wider windows).
MotionPlan planMotion(const Plan& plan, const Cell& cell, const MotionOptions& options = {},
                      const Progress& progress = {});

/// Estimates only (no kinematics): bead length, times, wire, mass per layer and total.
/// `layers` has one entry per plan layer. Cost: O(points).
MotionEstimate estimatePlan(const Plan& plan, const ProcessDescription& process,
                            std::vector<MotionEstimate>* layers = nullptr);

/// Station pulses of a positioner angle (model, rad): sign·round(deg·ppd); InvalidInput if ppd 0.
long long positionerPulses(const PositionerAxis& axis, double angle);

/// Controller pulses of robot joints (controller convention, rad); throws InvalidInput if the
/// cell has no pulsesPerDegree.
std::array<long long, 6> robotPulses(const RobotDescription& robot, const JointVector& joints);

}  // namespace curvedslicer
