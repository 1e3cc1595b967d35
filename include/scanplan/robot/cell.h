#pragma once
// The inspection cell (docs/cell.md): the robot carrying the scanner, where it stands, how
// the scanner is mounted on its flange, and an optional rotary table under the part.
// A view is feasible when the robot reaches it (some table angle, some inverse-kinematics
// solution within the joint limits).

#include <scanplan/cad/mesh.h>
#include <scanplan/core/view.h>
#include <scanplan/robot/kinematics.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

// A turntable carrying the part: it turns about `axis` through `origin` (world frame).
// The plan is made with the table at angle 0; at angle a, the part and every view of it
// are turned by a about the axis.
struct RotaryTable {
  Vec3 origin = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();           // unit
  double lower = -M_PI, upper = M_PI;  // radians
  double step = radians(5);            // angles tried, radians
  double speed = M_PI / 2;             // its top speed, rad/s: a quarter turn a second
  double acceleration = M_PI / 2;      // rad/s²: its top speed in a second (docs/cycle.md)
  // Its mechanical unit as the controller's system parameters name it: RAPID's work object
  // is coordinated with it.
  std::string unit = "STN_1";
};

// The table's own frame, turning with it, at angle 0 (world): its origin, z along its axis,
// x along the world's x (else y) laid into its plane. RAPID's coordinated work object gives
// the part in this frame.
Pose tableFrame(const RotaryTable& table);

// The scanner as the robot's load, for the controller's payload: its mass and centre of
// gravity in the flange frame. The default stands for a 2 kg head centred on the mount's
// origin; give the scanner's data-sheet values in the spec (cell.tool).
struct ToolLoad {
  double mass = 2;             // kg
  std::optional<Vec3> centre;  // mm, flange frame; none: the mount's origin
  // Principal moments of inertia about the centre of gravity, axes along the flange's,
  // kg·m²; none: the scanner's body as a uniform box of that mass (loadInertia).
  std::optional<Vec3> inertia;
};

// The signals of a rotary table that URScript drives (KRL and RAPID drive it as an
// external axis): the angle (degrees) to float output register `angle`, output `move`
// raised until input `ready` rises, then both dropped.
struct TableSignals {
  int angle = 0, move = 0, ready = 0;
};

// The controller's signals, numbered as the controller counts them (docs/cell.md). At
// each view the program writes the view number to group output (KRL, RAPID) or integer
// output register (URScript) `view`, raises output `trigger`, waits for input
// `acknowledge`, drops the trigger and waits for the acknowledgement to drop. Each wait on
// an input lasts `timeout` seconds at most; then the program stops the cell with an error.
struct CellSignals {
  int view = 2, trigger = 1, acknowledge = 1;  // KRL: the view number on $OUT[2] to $OUT[17]
  std::optional<TableSignals> table;           // none: URScript cannot drive the table
  double timeout = 10;                         // s
};

struct Cell {
  RobotModel robot;
  Pose base = Pose::Identity();   // the robot's base frame in the world
  Pose mount = Pose::Identity();  // the scanner frame S in the flange frame
  std::optional<RotaryTable> table;
  double clearance = 10;  // mm the arm keeps from the part, fixtures and working plane
  ToolLoad tool;
  CellSignals signals;
  // Safe motion (robot/motion.h): the home joints (none: computed above the part) and the
  // approach distance along each view's axis, mm.
  std::optional<Joints> home;
  double approach = 100;
  // Kept from each joint's limits by every pose the planner and the programs choose,
  // radians: the controller stops an axis at its software limit, and a pose on it leaves no
  // room to move.
  double joint_margin = radians(2);
  // Meshes of the upper arm, the forearm and the wrist in the robot's base frame at the
  // zero pose (linkMotions), used for collisions instead of the capsules; empty: capsules.
  std::vector<TriangleMesh> link_meshes;
};

// Checks `cell` against the ranges of the spec's cell section (docs/cell.md): the robot,
// the table's axis, range and step, clearance, tool, signals, home, approach and joint
// margin. The one check of a cell, whether it comes from a spec or a plan.
// \throw InputError naming `source` and the key.
void validate(const Cell& cell, const std::string& source);

// The table turned by `angle` (radians), world frame: identity without a table.
Pose tableTurn(const Cell& cell, double angle);

// Where the robot must put its flange (base frame) for the scanner to be at `view` with
// the table turned by `table_angle`.
Pose flangeFor(const Cell& cell, const View& view, double table_angle = 0);

// How the cell takes a view: the table angle and the joints.
struct CellPose {
  double table_angle = 0;  // radians
  Joints joints{};
};

// Why a view cannot be taken (the nearest miss over all table angles: collision before
// joint limits before out of reach).
enum class CellFailure { None, OutOfReach, JointLimits, Collision };
std::string_view toString(CellFailure failure);

struct CellReach {
  std::vector<CellPose> poses;  // every solution at the first table angle that has one
  CellFailure failure = CellFailure::None;
  bool reachable() const { return !poses.empty(); }
};

// Collisions of the robot and the scanner it carries with the part, its fixtures and the
// working plane: the upper arm, the forearm and the wrist as capsules
// (RobotModel::link_radii) grown by a safety margin, or as the cell's link meshes kept that
// margin away, and the scanner's body as a box grown by the margin, against the triangles
// of the part (FCL, bounding-volume hierarchies built once).
class CellCollisions {
 public:
  // The part placed by `part_to_world` with `fixtures` (world frame), at table angle 0;
  // `scanner_body` in the scanner frame S (Scanner::body; empty: the arm alone).
  CellCollisions(const Cell& cell, const Box& scanner_body, const TriangleMesh& part,
                 const Pose& part_to_world, const std::vector<TriangleMesh>& fixtures,
                 bool working_plane, double margin);
  ~CellCollisions();
  CellCollisions(const CellCollisions&) = delete;
  CellCollisions& operator=(const CellCollisions&) = delete;

  // True when a link of the robot or the scanner body at `pose` comes within the margin of
  // the part, a fixture or the working plane. Thread-safe.
  bool collides(const CellPose& pose) const;

  // An upper bound on how far any point of the robot or the scanner moves against the part
  // along the joint-interpolated move from `from` to `to` (the table turning with it), mm:
  // each joint's turn times the farthest a point can lie from its axis, and the table's
  // turn times the farthest a robot point, or a scene point, lies from the table's axis
  // (a robot point's when the axis is tilted, the working plane then moving against it).
  double travelBound(const CellPose& from, const CellPose& to) const;

  // The spacing of the configurations checked along a move (robot/motion.h), mm: half the
  // margin, so that no point moves more than that between two of them (at least 1 mm).
  double sampleSpacing() const;

  // The highest point of the part and the fixtures, world z, mm (0: nothing).
  double top() const;

  struct Capsule {
    Vec3 a, b;  // segment ends, world frame at table angle 0, mm
    double radius = 0;
  };
  // The links at `pose`, carried back with the table to the plan's frame.
  std::vector<Capsule> links(const CellPose& pose) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The cell's robot with each joint's limits drawn in by cell.joint_margin: the range the
// planner and the programs choose poses in.
RobotModel workingRange(const Cell& cell);

// The tool's moments of inertia for the controller's payload, kg·m²: cell.tool.inertia, or
// else `scanner_body` (the scanner frame's box, Scanner::body) as a uniform box of the
// tool's mass turned into the flange's axes by the mount (the diagonal of its inertia
// tensor there).
Vec3 loadInertia(const Cell& cell, const Box& scanner_body);

// The solutions for `view`: the table angles are tried from `preferred_angle` outwards
// (0, +step, -step, ...), the joints taken nearest to `near`; with `collisions`, only
// solutions whose arm stays clear (else failure Collision).
CellReach reachView(const Cell& cell, const View& view, const Joints& near = {},
                    double preferred_angle = 0, const CellCollisions* collisions = nullptr);

}  // namespace scanplan
