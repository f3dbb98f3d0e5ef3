// The robot cell: a six-axis spherical-wrist robot holding a vertical welding torch, a two-axis
// tilt-rotate positioner carrying the part, the welding process and the export options — read
// from a JSON cell description (schema: resources/schema/cell.schema.json, examples:
// resources/cells/*.json). The paper's cell (§4.1: Yaskawa Motoman HP20D with a tilt-rotate
// positioner) is `defaultCell()`.
//
// Frames (all lengths mm, all angles rad in C++; the JSON uses degrees where the key says `_deg`):
//   world       the cell frame; `Cell::gravity` is expressed in it (default (0,0,-1)).
//   robot base  `RobotDescription::base` = pose of the robot base frame in world.
//   flange      robot flange frame; `ToolDescription::tcp` = TCP frame in the flange frame.
//               The tool z axis is the torch axis, pointing out of the torch towards the wire tip.
//   positioner base  `PositionerDescription::base` = pose of the positioner base in world.
//   table       the frame turning with both positioner axes; at a1 = a2 = 0 its origin is
//               `rotationAxisPoint`, its z axis `rotationAxisDirection` and its x axis
//               `tiltAxisDirection` made orthogonal to z (both in positioner-base coordinates).
//   part        the plan's frame; `PositionerDescription::tableToPart` = part frame in table frame.
// Positioner forward kinematics (see positioner.hpp):
//   T_world_part = base · Rot(tiltAxis, a1 | tiltAxisPoint) · Rot(rotationAxis, a2 |
//   rotationAxisPoint)
//                  · T_base_table0 · tableToPart
//
// Robot joint angles in C++ are the controller's joint angles (rad), as the pendant shows them;
// `RobotDescription::jointSigns/jointOffsets` map them to the kinematic model of
// robot_kinematics.hpp (θ_model = sign · θ_controller + offset; with
// `RobotDescription::j3RelativeToHorizontal` (Fanuc), θ_model3 = sign3 · J3 + offset3 − θ_model2).
//
// Vendor: `Cell::vendor` names the controller family the cell is for (Yaskawa, KUKA, ABB, Fanuc);
// `checkCellVendor` refuses to write one vendor's program language for another vendor's cell.
// A file without "vendor" loads with RobotVendor::Unknown and a note (Cell::notes).
//
// Versions: version 2 (written by writeCellJson) adds the torch envelope (`tool/envelope`), the
// positioner's geometry (`positioner/geometry`) and the home pose (`home`). A version-1 file (the
// format before them) still loads: it gets the stated defaults (`TorchEnvelope{}`,
// `PositionerGeometry{}`, `HomePose{}`) and one entry in `Cell::notes` per default taken.
//
// Validation: every field is checked on reading; a missing or invalid field throws InvalidInput
// whose message names the JSON path (e.g. "/positioner/tilt/limits_deg") and why. Cost: trivial.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/robot/bead_model.hpp"

namespace curvedslicer {

using Pose = Eigen::Isometry3d;             ///< rigid transform, translation in mm
using JointVector = std::array<double, 6>;  ///< robot joints, rad, controller convention

/// Range and speed of one joint.
struct JointLimit {
  double min = -3.14159265358979323846;  ///< rad (controller convention)
  double max = 3.14159265358979323846;   ///< rad; min < max
  double maxSpeed = 3.0;                 ///< rad/s, > 0
  bool contains(double angle, double tolerance = 1e-9) const {
    return angle >= min - tolerance && angle <= max + tolerance;
  }
};

/// Geometry of a six-axis robot with an ortho-parallel arm and a spherical wrist (the usual
/// industrial arm: Motoman, KUKA, ABB, Fanuc). Model zero pose (all θ_model = 0): upper arm
/// vertical (+z), forearm horizontal (+x), wrist straight, flange z axis along +x, flange x axis
/// along -z. Joint axes: 1 = +z through the origin; 2 and 3 = +y (after joint 1), through
/// (a1, b, c1) and (a1, b, c1 + c2); 4 = forearm axis (+x) through the wrist centre
/// (a1 + c3, b, c1 + c2 + a2); 5 = +y through the wrist centre; 6 = +x (flange axis).
struct RobotKinematics {
  double a1 = 0.0;  ///< mm, horizontal offset of joint 2 from joint 1 (S-L offset)
  double a2 = 0.0;  ///< mm, offset of the forearm axis above joint 3 (U-axis offset)
  double b = 0.0;   ///< mm, lateral offset of the arm plane from joint 1 (usually 0)
  double c1 = 0.0;  ///< mm, height of joint 2 above the base frame
  double c2 = 0.0;  ///< mm, upper-arm length, joint 2 to joint 3 (> 0)
  double c3 = 0.0;  ///< mm, forearm length, joint 3 to the wrist centre along the forearm (> 0)
  double c4 = 0.0;  ///< mm, wrist centre to flange (>= 0)
};

/// A linear inequality between controller joint angles that the joint box cannot express:
/// Σ coefficients[i] · q[i] ≤ max (q and max in rad), e.g. Fanuc's J2/J3 interaction or
/// Yaskawa's L/U interference (the forearm folding onto the upper arm). Inverse kinematics never
/// offers a violating solution as within limits, the motion plan flags every violating point and
/// exporters refuse one. JSON robot/interference: [{"name", "coefficients", "max_deg"}].
struct JointInequality {
  std::string name;                      ///< e.g. "J2/J3", for messages
  std::array<double, 6> coefficients{};  ///< per controller joint, dimensionless, not all zero
  double max = 0.0;                      ///< rad
};

/// The robot arm for collision checks: capsules around the arm's kinematic segments
/// (computeArmPoints), in mm. The column on joint 1's axis from the floor (or the robot base
/// origin, when it is below the floor or the axis is not upright) to the height of joint 2; the
/// upper arm from joint 2 to joint 3, shifted `upperArmOffset` along joint 2's axis (industrial
/// upper arms sit beside the arm plane); the elbow housing from joint 3 up the forearm offset a2
/// to the forearm's axis (its radius also covers what reaches behind joint 3); the forearm along
/// that axis to the wrist centre; the wrist from the wrist centre to the flange. Every vertex of
/// the robot's published collision meshes lies in one of them (resources/cells/README.md gives
/// the source of each number). JSON robot/link_capsules_mm, required from cell version 3; all 0:
/// not known (a version-2 file), the arm is not checked.
struct ArmEnvelope {
  double column = 0.0;          ///< mm, radius: base and joint-1 housing
  double upperArm = 0.0;        ///< mm, radius: joint 2 to joint 3
  double upperArmOffset = 0.0;  ///< mm, signed, along joint 2's axis (model y at joint 1 = 0)
  double elbow = 0.0;           ///< mm, radius: joint-3 housing, joint 3 to the forearm's axis
  double forearm = 0.0;         ///< mm, radius: forearm's axis to the wrist centre
  double wrist = 0.0;           ///< mm, radius: wrist centre to the flange (joints 5 and 6)
  bool known() const { return column > 0.0; }
};

struct RobotDescription {
  std::string model;             ///< e.g. "Yaskawa Motoman HP20D"
  Pose base = Pose::Identity();  ///< robot base frame in world
  RobotKinematics kinematics;
  std::array<JointLimit, 6> joints;                      ///< controller convention
  std::array<double, 6> jointSigns{1, 1, 1, 1, 1, 1};    ///< ±1: θ_model = sign·θ_ctrl + offset
  std::array<double, 6> jointOffsets{0, 0, 0, 0, 0, 0};  ///< rad
  /// Fanuc: the controller's J3 is the forearm's angle to the horizontal (J2's motion does not
  /// move it), so the model's joint 3 (relative to the upper arm) is sign3·J3 + offset3 − θ_model2.
  bool j3RelativeToHorizontal = false;
  /// Encoder pulses per degree of each controller joint angle (pulse = round(deg · ppd));
  /// empty when not known — exporters must then write Cartesian robot positions.
  std::vector<double> pulsesPerDegree;
  /// The controller's Cartesian robot frame in the robot base frame: the frame from which a
  /// program's robot-frame positions are measured (JBI `POSTYPE BASE`, Fanuc world/UF 0). Yaskawa's
  /// robot coordinates and Fanuc's world frame lie on joint 1's axis at the height of joint 2,
  /// KUKA's and ABB's base frames at the robot's foot (defaultControllerFrame). JSON
  /// robot/controller_frame; when absent the reader takes the vendor's default and notes it.
  Pose controllerFrame = Pose::Identity();
  /// Joint interference limits beyond the joint box (JSON robot/interference; when absent the
  /// reader assumes none and notes it).
  std::vector<JointInequality> interference;
  /// Link capsules for collision checks (JSON robot/link_capsules_mm); not known in version-2
  /// files.
  ArmEnvelope links;
};

/// The largest amount (rad) by which `joints` (controller convention) exceed the robot's
/// interference limits; 0 or less when all hold (-infinity without limits).
double interferenceExcess(const RobotDescription& robot, const JointVector& joints);

/// The first interference limit `joints` violate by more than `tolerance` (rad), or nullptr.
const JointInequality* violatedInterference(const RobotDescription& robot,
                                            const JointVector& joints, double tolerance = 1e-9);

/// The torch body for collision checks: a truncated cone on the tool z axis. It starts at the
/// nozzle, `stickout` behind the TCP (the wire tip; against tool z, i.e. up the torch), with
/// radius `radius`, and ends `length` further up the torch with radius `topRadius`. The defaults
/// (taken for version-1 cells) describe a typical straight 400 mm WAAM / GMAW torch: nozzle
/// outer diameter 25 mm, 15 mm wire stick-out, neck and body within 50 mm diameter up to the
/// flange (400 - 15 = 385 mm); sources in resources/cells/README.md.
struct TorchEnvelope {
  double stickout = 15.0;   ///< mm, TCP to the nozzle tip along -tool z, >= 0
  double radius = 12.5;     ///< mm, radius at the nozzle, > 0
  double topRadius = 25.0;  ///< mm, radius at the top end, > 0
  double length = 385.0;    ///< mm, nozzle to top end along -tool z, > 0
};

struct ToolDescription {
  std::string name;             ///< e.g. "straight torch 400 mm"
  Pose tcp = Pose::Identity();  ///< TCP frame in the flange frame; its z axis is the torch axis
  int number = 1;               ///< tool number in the controller (TOOL 1)
  TorchEnvelope envelope;       ///< torch body for collision checks (tool frame)
};

/// One positioner axis.
struct PositionerAxis {
  JointLimit limit;              ///< rad, rad/s (ignored range when endless)
  bool endless = false;          ///< unlimited rotation (rotation axis only)
  double pulsesPerDegree = 0.0;  ///< > 0: pulse = sign · round(deg · ppd); 0: not known
  int sign = 1;                  ///< ±1, controller direction relative to the model direction
};

/// The positioner's table and working volume, in the table frame (origin on the rotation axis,
/// z along it): the table is a disc of `tableRadius` whose top face is the plane z = 0, extending
/// `tableThickness` below it; parts must fit in the cylinder of `maxPartRadius` about the
/// rotation axis between z = 0 and z = `maxPartHeight`. Defaults (taken for version-1 cells): a
/// D500B-class positioner, sources in resources/cells/README.md.
struct PositionerGeometry {
  double tableRadius = 300.0;    ///< mm, > 0
  double tableThickness = 30.0;  ///< mm, > 0
  double maxPartRadius = 350.0;  ///< mm, > 0, about the rotation axis
  double maxPartHeight = 500.0;  ///< mm, > 0, above the table top
  /// mm, radius of the positioner's body under the table: a cylinder on the rotation axis from
  /// the table's underside down to the tilt axis (the rotation drive and its housing), which
  /// tilts with the table. 0: not known (a version-2 file), not checked.
  double bodyRadius = 0.0;
};

/// What the part is built on, between the table and the part, in the table frame: a riser
/// (pedestal) standing on the table top, a cylinder of `riserDiameter` centred on the rotation
/// axis from z = 0 to z = `riserHeight`; on it (or on the table without a riser) a square
/// substrate plate of side `substrateSize` centred on the axis, `substrateThickness` thick. The
/// part rests on the fixture's top, z = riserHeight + substrateThickness. Zero heights: no riser,
/// no plate (the part on the bare table, the default).
struct FixtureGeometry {
  double riserHeight = 0.0;         ///< mm, >= 0; > 0 needs riserDiameter > 0
  double riserDiameter = 0.0;       ///< mm, >= 0, at most the table's diameter
  double substrateThickness = 0.0;  ///< mm, >= 0; > 0 needs substrateSize > 0
  double substrateSize = 0.0;       ///< mm, side of the square plate, >= 0
  /// Table z of the surface the part rests on (mm).
  double top() const { return riserHeight + substrateThickness; }
  bool hasRiser() const { return riserHeight > 0.0; }
  bool hasSubstrate() const { return substrateThickness > 0.0; }
};

/// A clear InvalidInput naming the field (`origin` + "riser_height_mm" …, `origin` e.g.
/// "cell.json: field /positioner/fixture/") when `fixture` is not a fixture that fits `geometry`:
/// negative or non-finite sizes, a riser or plate without its width, a riser wider than the
/// table, a plate wider than the working volume, a fixture as high as the working volume.
void validateFixture(const FixtureGeometry& fixture, const PositionerGeometry& geometry,
                     std::string_view origin);

struct PositionerDescription {
  std::string model;                       ///< e.g. "two-axis tilt-rotate positioner (D500B class)"
  Pose base = Pose::Identity();            ///< positioner base frame in world
  Vec3 tiltAxisPoint = Vec3::Zero();       ///< mm, positioner base frame
  Vec3 tiltAxisDirection = Vec3::UnitX();  ///< unit; a1 > 0 turns right-handed about it
  Vec3 rotationAxisPoint = Vec3::Zero();   ///< mm, positioner base frame at a1 = 0
  Vec3 rotationAxisDirection = Vec3::UnitZ();  ///< unit, at a1 = 0; a2 > 0 right-handed
  Pose tableToPart = Pose::Identity();         ///< part frame in the table frame
  PositionerAxis tilt;                         ///< a1
  PositionerAxis rotation;                     ///< a2
  PositionerGeometry geometry;                 ///< table disc and working volume
  FixtureGeometry fixture;                     ///< riser and substrate plate on the table
};

/// Where the program starts and ends: robot joints and positioner angles. The default (taken
/// for version-1 cells) is the robot's controller zero (all joints 0) and the positioner at 0, 0.
struct HomePose {
  JointVector robot{0, 0, 0, 0, 0, 0};  ///< rad, controller convention, within the joint limits
  double a1 = 0.0;                      ///< rad, positioner tilt (model convention), in limits
  double a2 = 0.0;                      ///< rad, positioner rotation (model convention)
};

enum class SpeedUnit { MillimetresPerSecond, CentimetresPerMinute, MillimetresPerMinute };
enum class ArcControl { ConditionFile, Direct };
enum class PositionType { Pulse, Base, User };
enum class LineEnding { Crlf, Lf };

/// s, the minimum layer time of a cell file that gives none: WAAM slicers' usual interpass
/// cooling floor for small layers
inline constexpr double kDefaultMinLayerTime = 30.0;

struct ProcessDescription {
  double weldSpeed = 8.0;             ///< mm/s, torch speed relative to the part with the arc on
  double travelSpeed = 50.0;          ///< mm/s, arc-off moves between paths
  double wireFeed = 5.0;              ///< m/min, wire feed speed
  double wireDiameter = 1.2;          ///< mm
  double wireDensity = 7.85;          ///< g/cm³ (steel)
  double depositionEfficiency = 1.0;  ///< (0, 1], deposited / fed mass (spatter loss)
  double layerDwell = 0.0;            ///< s, wait after each layer (interpass cooling)
  double pathDwell = 0.0;             ///< s, wait after each path
  /// s, minimum layer time (JSON "min_layer_time_s", 0..86400, default 30; 0 = off): a layer
  /// whose welding, travel and dwells take less waits the rest after its last path, so that a
  /// small layer is not welded onto one still hot from the layer before (timing.hpp)
  double minLayerTime = kDefaultMinLayerTime;
  /// rad (15°), the torch window: the largest angle of the torch off gravity the planner may use
  /// to clear deposit, table and fixture (JSON "max_torch_angle_deg", 0..45; 0 = always along
  /// gravity). GMA tolerates push/drag and work angles of about 0-15°, up to 20-25° in WAAM.
  double maxTorchAngle = 0.261799387799;
  /// rad (10°), the gravity deviation window: where no torch angle within the torch window
  /// clears the deposit, the table or the fixture, the positioner may turn the deposition
  /// direction up to this far off gravity, towards the torch's lean, so that the torch, still
  /// within the torch window off gravity, leans this much further against the part (JSON
  /// "max_gravity_deviation_deg", 0..45; 0 = V always on gravity where the positioner can turn
  /// it there). A few degrees off flat do not spoil a GMA bead; 10° is a common bound.
  double maxGravityDeviation = 0.174532925199;
  SpeedUnit speedUnit = SpeedUnit::MillimetresPerSecond;  ///< unit the controller expects
  ArcControl arcControl = ArcControl::ConditionFile;
  int arcStartCondition = 1;  ///< ASF#(n) condition-file number
  int arcEndCondition = 1;    ///< AEF#(n)
  double current = 0.0;       ///< A, direct arc condition (ArcControl::Direct), > 0 then
  double voltage = 0.0;       ///< V, direct arc condition
  double arcStartTime = 0.0;  ///< s, crater / start time for direct conditions
  /// Bead width and height over WFS × TS (robot/bead_model.hpp), JSON
  /// "process"/"bead_model" (optional); empty = none: every weld at weldSpeed and wireFeed.
  BeadModel beadModel;
};

struct ExportDescription {
  bool coordinated = true;  ///< robot and positioner move together (SMOVL ... +MOVJ)
  PositionType positionType = PositionType::Base;  ///< robot targets: Cartesian or pulses
  int maxLinesPerJob = 2000;                       ///< split longer jobs into sub-jobs
  LineEnding lineEnding = LineEnding::Crlf;
  std::string jobName = "WAAM";  ///< base name of the job(s)
  int maxNameLength = 8;         ///< 8 (NX100) or 32 (DX100 and later)
  int userFrame = 1;             ///< user frame number for PositionType::User
};

/// The controller family a cell is for; decides which program languages fit it (jbi: Yaskawa,
/// krl: KUKA, rapid: ABB, ls: Fanuc; gcode, csv and json fit every cell).
enum class RobotVendor { Unknown, Yaskawa, Kuka, Abb, Fanuc };

// ---- controller (vendor-specific program settings) -------------------------------------------
/// KUKA KRL settings (cell "controller"/"krl"; export/krl_writer.hpp).
struct KrlController {
  int arcOnOutput = 1;                 ///< $OUT[n] that switches the arc on (1..4096); required
  int arcEstablishedInput = 0;         ///< $IN[m] waited for after arc on (1..4096); 0 = no wait
  int wireFeedAnalogOutput = 0;        ///< $ANOUT[n] carrying the wire feed (1..32); 0 = none
  double wireFeedFullScale = 0.0;      ///< m/min at $ANOUT = 1.0; > 0 when an output is named
  double approximationDistance = 1.0;  ///< mm, $APO.CDIS used by C_DIS between weld points
  int baseNumber = 1;                  ///< BASE_DATA[n] of the table (coordinated) frame (1..32)
  int maxLinesPerFile = 0;             ///< .src lines before a split; 0 = export max_lines_per_job
};

/// ABB RAPID settings (cell "controller"/"rapid"; export/rapid_writer.hpp). The arc is a plain
/// digital output (no ArcWare seamdata/welddata).
struct RapidController {
  std::string arcSignal;             ///< DO switching the arc on, e.g. "doArcOn"; required
  std::string arcEstablishedSignal;  ///< DI waited for (WaitDI) after arc on; "" = no wait
  std::string wireFeedSignal;        ///< AO set to the wire feed (m/min); "" = not written
  std::string mechUnit;   ///< positioner mechanical unit, e.g. "STN1"; required if coordinated
  double toolMass = 0.0;  ///< kg, load of the declared tooldata, > 0; required
  Vec3 toolCog = Vec3::Zero();  ///< mm, its centre of gravity in the flange frame
  int maxLinesPerModule = 0;    ///< module lines before a split; 0 = export max_lines_per_job
};

// ---- controller: Fanuc LS and Yaskawa JBI settings (branch s9-export2) -----------------------
/// Fanuc ArcTool settings (JSON controller/ls); required for an LS export.
struct LsControllerSettings {
  int weldEquipment = 1;          ///< /APPL `ARC Welding Equipment : n` (1..2)
  int arcStartSchedule = 1;       ///< `Arc Start[n]`: weld schedule number (1..99)
  int arcEndSchedule = 1;         ///< `Arc End[n]`: crater / end schedule number (1..99)
  int maxLinesPerProgram = 2000;  ///< /MN lines per program; longer programs are split (>= 20)
};

/// Yaskawa settings beyond process/arc (JSON controller/jbi); optional.
struct JbiControllerSettings {
  /// > 0: `WAIT IN#(n)=ON` after every ARCON, the input the welder sets once the arc is
  /// established (ARCON itself waits for the arc-confirm signal where the welder sends it); 0:
  /// none.
  int arcWaitInput = 0;
};

/// Vendor-specific settings of the programs (cell "controller"). Members of one vendor are absent
/// when the cell does not describe that controller; the writer of that vendor's language then
/// stops with an error naming the missing JSON field and `source`.
struct ControllerDescription {
  std::string source = "cell";  ///< where the cell was read from (parseCell's origin); not written
  std::optional<KrlController> krl;          ///< controller/krl
  std::optional<RapidController> rapid;      ///< controller/rapid
  std::optional<LsControllerSettings> ls;    ///< controller/ls
  std::optional<JbiControllerSettings> jbi;  ///< controller/jbi
};

struct Cell {
  std::string name;
  RobotVendor vendor = RobotVendor::Unknown;  ///< Unknown: no "vendor" given (a note says so)
  std::string description;                    ///< free text, incl. sources of the numbers
  Vec3 gravity = -Vec3::UnitZ();              ///< unit, world frame
  RobotDescription robot;
  ToolDescription tool;
  PositionerDescription positioner;
  ProcessDescription process;
  ExportDescription exportOptions;
  ControllerDescription controller;  ///< vendor-specific program settings
  HomePose home;
  /// What the reader assumed, e.g. the defaults of a version-1 file ("cell version 1: default
  /// torch envelope ... assumed; add tool/envelope"); planMotion copies them into
  /// MotionPlan::notes. Not written by writeCellJson.
  std::vector<std::string> notes;
};

/// The cell format version writeCellJson writes and the newest parseCell reads.
inline constexpr int kCellFormatVersion = 3;

/// Reads and validates a cell description file (JSON). Throws IoError if the file cannot be read,
/// InvalidInput naming the JSON path of a missing or invalid field.
Cell readCell(const std::filesystem::path& path);

/// Parses and validates a cell description from JSON text; `origin` names the source in
/// messages (e.g. the file name).
Cell parseCell(std::string_view json, std::string_view origin = "cell");

/// Checks a cell built in code (the same rules as parseCell); throws InvalidInput naming the
/// field (as its JSON path).
void validateCell(const Cell& cell);

/// Serialises a cell to the JSON form parseCell reads, version kCellFormatVersion (numbers
/// rounded to 9 significant digits, so a round trip reproduces the same text; notes are not
/// written).
std::string writeCellJson(const Cell& cell);

/// The paper's cell: Yaskawa Motoman HP20D, a D500B-class tilt-rotate positioner, straight torch;
/// sources of the numbers in resources/cells/README.md. Equal to
/// parseCell(resources/cells/motoman_hp20d_tilt_rotate.json).
Cell defaultCell();

/// Throws InvalidInput when `format` (an export format name: jbi, krl, rapid, ls, gcode, csv,
/// json) is one vendor's program language and the cell is another vendor's, unless
/// `allowForeign`; the message names the cell's vendor and the format. Also refuses jbi for a cell
/// whose positioner axes have no pulses_per_degree (JBI station positions are pulses). Neutral
/// formats and cells of unknown vendor pass.
void checkCellVendor(const Cell& cell, std::string_view format, bool allowForeign);

/// The vendor whose controller runs `format` (jbi → Yaskawa, krl → KUKA, rapid → ABB,
/// ls → Fanuc); Unknown for the neutral formats (gcode, csv, json) and unknown names.
RobotVendor vendorOfFormat(std::string_view format);

/// The controller's Cartesian robot frame in the robot base frame by the vendor's convention:
/// Yaskawa (robot coordinates) and Fanuc (world frame) on joint 1's axis at the height of
/// joint 2, i.e. translated by (0, 0, c1); KUKA ($ROBROOT), ABB (base frame) and an unknown vendor
/// at the robot base frame itself (identity). Sources: resources/cells/README.md.
Pose defaultControllerFrame(RobotVendor vendor, const RobotKinematics& kinematics);

/// Names used in the JSON form, for messages and exporters.
std::string_view toString(RobotVendor vendor);
std::string_view toString(SpeedUnit unit);
std::string_view toString(ArcControl control);
std::string_view toString(PositionType type);
std::string_view toString(LineEnding ending);

/// Pose from translation (mm) and fixed-axis roll/pitch/yaw (rad): R = Rz(yaw)·Ry(pitch)·Rx(roll).
Pose makePose(const Vec3& translation, const Vec3& rollPitchYaw);

/// Inverse of makePose's rotation part: roll, pitch, yaw (rad), pitch in [-π/2, π/2].
Vec3 rollPitchYaw(const Mat3& rotation);

}  // namespace curvedslicer
