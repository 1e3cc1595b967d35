#pragma once
// View planning (DESIGN.md §5): poses from clusters and their visibility maps, iterative
// adding until nothing more can be covered, pruning by marginal coverage; then the
// registration check with bridging views, and the sequence.

#include <scanplan/cad/part.h>
#include <scanplan/clustering.h>
#include <scanplan/localization.h>
#include <scanplan/progress.h>
#include <scanplan/registration.h>
#include <scanplan/sampling.h>
#include <scanplan/sequencing.h>
#include <scanplan/simulation.h>
#include <scanplan/spec.h>
#include <scanplan/sweep.h>
#include <scanplan/view.h>

#include <optional>
#include <string>
#include <vector>

namespace scanplan {

struct PlanningOptions {
  double vm_step = 5;                   // visibility-map grid, degrees
  double tilt_min = 30, tilt_max = 50;  // preferred tilt of tilted positioning, degrees
  int max_failures = 3;                 // a sample not measured after more attempts is excluded
  int rotations = 8;                    // rotations about the view axis tried per direction
  double sweep_overlap = 0.3;           // share of the field of view sweep tiles share
  std::uint64_t seed = 1;
  double body_margin = 60;       // scanner body: box around camera and projector, grown by
  double body_depth = 200;       // this margin, reaching this far behind the camera, mm
  bool bound = false;            // also solve the exact set cover over all candidate poses
  double bound_time_limit = 30;  // seconds for CBC
  bool registration = true;      // check registration, bridge, and sequence the views
  std::optional<Cell> cell;      // the robot must reach every view (spec cell.robot)
  // Its arm against the part; made by the planner for each placement of the part.
  std::shared_ptr<const CellCollisions> collisions;
};

// The optimality check: the fewest candidate poses that measure every sample the plan
// measures (exact set cover, COIN-OR CBC).
struct PlanBound {
  std::size_t candidates = 0;  // valid poses the planner evaluated
  std::size_t ilp_views = 0;   // views of the best cover CBC found
  double lower_bound = 0;      // CBC's proven lower bound on the minimum
  bool optimal = false;        // ilp_views is proven minimal
  double seconds = 0;
};

// The planner's options as the spec's planner section sets them.
PlanningOptions planningOptionsFor(const Spec& spec);

// The simulation of `part` placed by `part_to_world` as the spec sets it: working plane
// and specular faces. \throw InputError for a specular face the part does not have.
SimulationOptions simulationOptionsFor(const Part& part, const Spec& spec,
                                       const Pose& part_to_world);

// Why a sample is not coverable.
enum class Uncoverable {
  None,
  BelowWorkingPlane,
  OccludedByPart,
  NoValidPose,
  Lost,
  Unreachable  // poses clear of the part measure it, but the cell's robot reaches none
};

struct PlannedSample {
  Sample sample;                 // world frame
  std::vector<int> measured_by;  // view ids
  int failures = 0;
  Uncoverable uncoverable = Uncoverable::None;
  Loss last_loss = Loss::Measured;  // why the last view aimed at it missed it
};

struct StageTime {
  std::string stage;
  double seconds = 0;
};

// A surface wider than the field of view covered tile by tile (DESIGN.md §5, Sweep
// positioning): the gdt task's wide faces over their own parameters, the surface task's
// faces over an interpolated patch per set of like-facing faces.
struct Sweep {
  TaskType task = TaskType::Surface;
  std::vector<int> faces;
  std::size_t tiles = 0;                   // tiles holding part of the surface
  std::vector<int> views;                  // ids of the tiles' views, boustrophedon order
  std::optional<InterpolatedPatch> patch;  // surface task: the patch swept along
  std::string patch_file;  // where the patch was written, beside plan.json; "" if not
};

// One rest orientation of a plan over several (part.rest: all): the views planned with
// the part standing that way, registered and sequenced among themselves.
struct PlannedOrientation {
  RestOrientation rest;
  std::vector<int> views;       // ids
  int reference = 0;            // its registration's reference view id
  std::vector<Marker> markers;  // world frame of this orientation
};

struct Plan {
  std::string part_file;
  std::size_t part_faces = 0;
  std::size_t fixture_faces = 0;
  Pose part_to_world = Pose::Identity();
  Scanner scanner;
  std::vector<View> views;  // ids 1..n in order of marginal coverage, then bridging views
  std::vector<Marker> markers;
  std::optional<Registration> registration;  // per view, with PlanningOptions::registration
  std::optional<Sequence> sequence;          // of the registered views
  std::vector<Sweep> sweeps;                 // their views come first, in sweep order
  // part.rest: all: the orientations planned, steadiest first. part_to_world and the
  // samples' frame are the first one's; each view is planned in the world of the
  // orientation that lists it; registration and sequence are per orientation, one after
  // the other. Empty for a plan with one placement.
  std::vector<PlannedOrientation> orientations;
  std::vector<PlannedSample> samples;
  // With a cell (spec cell.robot): the cell, and how it takes each view (per view, in the
  // order of the views; none where it cannot), the joints chosen along the sequence for
  // the least joint travel.
  std::optional<Cell> cell;
  std::vector<std::optional<CellPose>> cell_poses;
  std::vector<StageTime> times;
  double seconds = 0;
  std::optional<PlanBound> bound;  // with PlanningOptions::bound

  std::size_t measuredCount() const;
  std::size_t notCoverableCount() const;
  // Samples measured by a view that registers (all measured ones without registration).
  std::size_t registeredMeasuredCount() const;
};

// The spec's markers: its CSV, or its grid around the footprint of the part placed by
// `part_to_world` and/or on the part; none when it names neither.
std::vector<Marker> specMarkers(const Spec& spec, const Part& part, const Pose& part_to_world);

// The part standing on the working plane as it lies in its CAD frame: lifted so that its
// lowest point is at z = 0 (rest orientations come with localization).
Pose restingPlacement(const Part& part);

// Where the spec puts the part: part.rest's matrix, the rest orientation on its face, the
// steadiest one (auto, and the first of all), else restingPlacement. \throw InputError
// for a rest face the part cannot stand on.
Pose placementFor(const Part& part, const Spec& spec);

// Plans the views for the spec's tasks; with part.rest: all, in every rest orientation in
// turn, steadiest first, each aiming at the samples the earlier ones left unmeasured.
// \throw PlanningError when the spec leaves nothing
// to plan (no samples, or all targets on fixture faces); InputError for a bad spec.
Plan planViews(const Part& part, const Spec& spec, const PlanningOptions& options = {},
               const Progress& progress = {});

// True when the scanner body at `view` stays clear of the part, fixtures and the working
// plane, and the cell's robot (PlanningOptions::cell) reaches it.
bool poseIsValid(const Simulator& simulator, const View& view, const PlanningOptions& options);

std::string_view toString(Uncoverable reason);

// The ids of the plan's views in the order they are visited: its sequence, then any view
// outside it in plan order.
std::vector<int> visitingOrder(const Plan& plan);

// Per view, every way the cell takes it: the inverse-kinematics solutions at the table
// angle nearest 0 that reaches it (with `collisions`, those whose arm stays clear), and
// the other turns of wide axes; empty where the cell cannot take the view.
using CellSolutions = std::vector<std::vector<CellPose>>;
CellSolutions cellSolutions(const Cell& cell, const std::vector<View>& views,
                            const CellCollisions* collisions = nullptr);

// How the cell takes each of `views` when they are visited in `order` (ids): of each
// view's `solutions`, the ones whose joints travel least from view to view over the whole
// order (dynamic programming). Per view, in the order of `views`; none where the cell
// cannot take the view.
std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellSolutions& solutions);
// The same with the views' solutions computed.
std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellCollisions* collisions = nullptr);

// The cell's motion cost between every two views: the least joint travel time over their
// `solutions` (seconds; the cell's joint speeds, the table at a quarter turn per second),
// 1000 s to or from a view the cell cannot take.
Eigen::MatrixXd jointTravelTimes(const Cell& cell, const CellSolutions& solutions);

// The joint motion of a sequence of cell poses: the largest change of any joint between
// consecutive reached views (radians), the travel time (seconds, joints at their largest
// speeds, the table at `table_speed` rad/s) and how often the table turns.
struct JointMotion {
  double max_step = 0;
  int max_step_joint = 0;  // 1-based
  double seconds = 0;
  std::size_t table_moves = 0;
  std::size_t unreached = 0;  // views the cell cannot reach
};
JointMotion jointMotion(const Cell& cell, const std::vector<std::optional<CellPose>>& poses,
                        const std::vector<View>& views, const std::vector<int>& order,
                        double table_speed = M_PI / 2);

// What `scanplan verify` finds when it checks a plan again on its part.
struct PlanCheck {
  Plan plan;  // the plan with measured_by, registration and path length recomputed
  std::size_t coverage_differences = 0;      // samples whose measured_by differs from the file's
  std::size_t registration_differences = 0;  // views whose registration state differs
  std::size_t sequence_missing = 0;          // views not in the sequence, or in it more than once
  std::size_t sequence_breaks = 0;  // registered views that follow no view they register to
};

// Simulates every view of `plan` on its samples again, checks the registration of its
// views (no bridging) and walks its sequence, with the part placed as the plan says and
// the spec's specular faces, markers (else the plan's) and registration thresholds.
// \throw InputError when the part does not match the plan (face count).
PlanCheck verifyPlan(const Plan& plan, const Part& part, const Spec& spec,
                     const PlanningOptions& options = {}, const Progress& progress = {});

// Which samples some valid pose of a dense candidate set measures: the camera at the
// standoff from the sample itself, looking at it, from every direction of a `step`-degree
// grid within the camera's glancing cone, each with `rotations` rotations about the view
// axis, its scanner body (sized by `body`) clear. The reference of coverage in
// benchmarks and reports; the planner's last pass aims at such poses too.
std::vector<char> coverableByDenseCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples,
                                             const PlanningOptions& body = {}, double step = 10,
                                             int rotations = 8);

}  // namespace scanplan
