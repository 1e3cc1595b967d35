#pragma once
// The plan (docs/design.md, plan.json): the views, what each sample is measured by, the
// registration and the sequence of the views; io/plan_json.h writes and reads it.

#include <scanplan/cad/gdt.h>
#include <scanplan/cad/localization.h>
#include <scanplan/cad/patch.h>
#include <scanplan/core/view.h>
#include <scanplan/registration/registration.h>
#include <scanplan/registration/sequencing.h>
#include <scanplan/robot/cell.h>
#include <scanplan/robot/cycle.h>
#include <scanplan/robot/motion.h>
#include <scanplan/sampling/sampling.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

// How close the selection came to the fewest views of its pool (docs/planning.md): the
// views kept against the lower bound of the pool's set cover (its LP relaxation, raised by
// CBC's search).
struct PlanBound {
  std::size_t views = 0;         // views the selection kept (bridging views not counted)
  std::size_t greedy_views = 0;  // views of the greedy cover the selection started from
  double lower_bound = 0;        // no cover of the pool's reachable samples has fewer views
  std::size_t pool = 0;          // candidate poses, each simulated on the samples
  bool proven_optimal = false;   // views is the minimum over the pool (lower_bound >= views)
  bool time_capped = false;      // planner.selection_seconds stopped the exact selection before
                                 // planner.selection_nodes: the plan depends on the machine
};

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
  Uncoverable uncoverable = Uncoverable::None;
  Loss last_loss = Loss::Measured;  // why the last view aimed at it missed it
};

// A face's area and how much of it some view of the plan measures (docs/planning.md,
// "Coverage by area"), mm².
struct FaceArea {
  int face = 0;
  double area = 0;
  double measured = 0;
};

struct StageTime {
  std::string stage;
  double seconds = 0;
};

// A surface wider than the field of view covered tile by tile (docs/sweep.md): the gdt
// task's wide faces over their own parameters, the surface task's faces over an
// interpolated patch per set of like-facing faces.
struct SweepPatch {
  Vec3 direction = Vec3::UnitZ();  // the faces' mean direction it is seen along, part frame
  double tolerance = 0;            // approximation tolerance asked of the fit, mm
  double max_deviation = 0;        // largest |patch - face| height over the fitted nodes, mm
  PatchShape shape;                // to be written beside plan.json
};
struct Sweep {
  TaskType task = TaskType::Surface;
  std::vector<int> faces;
  std::size_t tiles = 0;            // tiles holding part of the surface
  std::vector<int> views;           // ids of the tiles' views, boustrophedon order
  std::optional<SweepPatch> patch;  // surface task: the patch swept along
  std::string patch_file;           // its file beside plan.json (patch-K.step); "" if none
};

// One rest orientation of a plan over several (part.rest: all): the views planned with
// the part standing that way, registered and sequenced among themselves.
struct PlannedOrientation {
  RestOrientation rest;
  std::vector<int> views;       // ids
  int reference = 0;            // its registration's reference view id
  std::vector<Marker> markers;  // world frame of this orientation
  // The setup whose frame its views register in (an index into Plan::orientations): its
  // own, or the first of the setups that markers on the part join with it (joinSetups).
  std::size_t frame = 0;
};

enum class Verdict { Capable, Marginal, NotCapable, Untoleranced };
std::string_view toString(Verdict verdict);  // "capable", "marginal", "not_capable", ...

// Why a characteristic is not capable: most of its faces unmeasured, too few points or too
// much of the faces left out, or the error budget too large for the tolerance; or, behind
// "uncovered", the import linked it to no face, its faces are measured only by views that
// register to nothing, or they are measured in setups whose frames are not joined.
enum class Shortfall {
  None,
  Uncovered,
  TooSparse,
  TooUncertain,  // U too large for the tolerance, whatever its sources
  NotLinked,
  NotRegistered,
  SetupsNotJoined,
  DatumsUnmeasured  // less than half its datum features' area measured: no frame to fit
};
constexpr int kShortfalls = 8;
// "none", "uncovered", "too_sparse", "too_uncertain", "not_linked", "not_registered",
// "setups_not_joined", "datums_unmeasured"
std::string_view toString(Shortfall reason);

// Why a characteristic left short of capable is beyond what the views can do
// (docs/capability.md, "Limits"); None where it is capable, or more views may help.
enum class Limit {
  None,
  NotLinked,          // the import linked it to no face, or a datum to none
  NotTargeted,        // no task samples its faces: the planner did not aim at them
  NoPoseReaches,      // the planner's search found no pose for enough of its faces
  SetupsNotJoined,    // measured enough only across setups whose frames are not joined
  NotRegistered,      // measured enough only with views that register to nothing
  BelowScannerError,  // the scanner's acceptance error alone is too large for the tolerance
  RegistrationError   // the views' registration errors alone are too large for it
};
constexpr int kLimits = 8;
// "none", "not_linked", "not_targeted", "no_pose_reaches", "setups_not_joined",
// "not_registered", "below_scanner_error", "registration_error"
std::string_view toString(Limit limit);

// What U is made of (docs/capability.md, "Error budget"), each the expanded uncertainty
// (95%) of the characteristic's value from that source alone, mm (degrees for an angle).
struct ErrorBudget {
  double noise = 0;         // the scanner's random noise at each point
  double registration = 0;  // the views' registration errors, along their chains
  double scanner = 0;       // the scanner's acceptance figures (VDI/VDE 2634 part 2)
};

struct Capability {
  int characteristic = 0;  // its id
  double area = 0;         // of its faces, mm²
  double covered = 0;      // share of that area some view measures, 0..1
  double points = 0;       // points the views measure on it (expected count)
  double density = 0;      // points per mm² of the covered area
  double largest_gap = 0;  // mm: the farthest a point of the faces lies from a measured one
  double uncertainty = 0;  // U, mm: the budget's sources together (root sum of squares)
  ErrorBudget budget;
  double ratio = 0;  // width / (2 U)
  Verdict verdict = Verdict::NotCapable;
  Shortfall reason = Shortfall::None;
  Limit limit = Limit::None;
  std::vector<int> views;  // ids of the views that measure its faces in its frame
  // The virtual inspection's U and bias of its value (docs/capability.md, "Virtual
  // inspection"), under planner.aim characteristics, and how precisely its runs know
  // U + |bias| (± at 95 %, InspectedCharacteristic::precision).
  std::optional<double> inspected_uncertainty, inspected_bias, inspected_precision;
  // Where its faces lie unmeasured on the working plane: the index (into
  // restOrientations(part)) of the rest orientation that turns most of them up.
  std::optional<std::size_t> rest;
};

// How many characteristics a plan's first `views` views make capable.
struct CapableCount {
  std::size_t views = 0;
  std::size_t capable = 0;
};

// The spec a plan was made with, as it was read: its file (absolute; as given when it names
// no file, "<dict>" for one from Python), its text, and how the part stands where that was
// given over the text's part.rest (`plan --rest`, Spec::rest_given; "" none).
struct PlanSpec {
  std::string file;
  std::string text;
  std::string rest;
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
  // Where views register to nothing, markers that would register them (world frame).
  std::optional<MarkerProposal> proposed_markers;
  std::optional<Sequence> sequence;  // of the registered views
  std::vector<Sweep> sweeps;         // their views come first, in sweep order
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
  std::optional<CellMotion> cell_motion;  // of the program along the sequence
  // What a run takes (robot/cycle.h): by the cell's program, or without a cell by the
  // generic positioning along the sequence; none without either.
  std::optional<CycleTime> cycle;
  // The part's characteristics (its GD&T) and whether the views can verify each
  // (planning/capability.h), in the same order.
  std::vector<Characteristic> characteristics;
  std::vector<Capability> capabilities;
  // How many the first views make capable (capableByViews): the trade-off chart's curve.
  std::vector<CapableCount> capable_by_views;
  // Per face of the part, in face order: its measured area (planning/coverage_area.h);
  // empty for a plan read from a version that had none.
  std::vector<FaceArea> face_areas;
  // The spec it was made with; none for the default one. The commands reading a plan take it
  // when given none.
  std::optional<PlanSpec> spec;
  std::vector<StageTime> times;
  double seconds = 0;
  std::optional<PlanBound> bound;  // of the selection; per orientation, summed

  // A face with priority samples the plan leaves unmeasured (none of its views, nor any
  // pose of the planner's pool, measures them).
  struct FaceShortfall {
    int face = 0;
    std::size_t samples = 0, measured = 0;  // its priority samples
  };
  std::vector<FaceShortfall> priorityShortfall() const;

  // The samples as the simulation measures them: position, normal, face (world frame).
  std::vector<SurfacePoint> samplePoints() const;

  std::size_t measuredCount() const;
  std::size_t notCoverableCount() const;
  // Samples measured by a view that registers (all measured ones without registration).
  std::size_t registeredMeasuredCount() const;

  // The plan as the method's authors table their results (their Table 2): the model's and
  // the fixtures' faces, the control points (the points tasks' samples; the targets, all
  // samples, when there are none) and those measured, the views, and the alignable ones
  // (registered; none without registration).
  struct ResultsRow {
    std::size_t model_faces = 0, fixture_faces = 0;
    bool control_points = false;  // points are control points, else targets
    std::size_t points = 0, acquired = 0;
    std::size_t views = 0;
    std::optional<std::size_t> alignable;
  };
  ResultsRow resultsRow() const;
};

std::string_view toString(Uncoverable reason);

// Appends to `merged` what `part`, the plan of a later rest orientation, found: its
// registration and its sequence (where both plans have one) and, per sample, the views
// measuring it; the ids of `part`'s views shifted by `offset`.
void appendOrientation(Plan& merged, Plan& part, int offset);

// The ids of the plan's views in the order they are visited: its sequence, then any view
// outside it in plan order.
std::vector<int> visitingOrder(const Plan& plan);

// Per view of `plan` (in its order), the index into Plan::orientations of the rest
// orientation it was planned in; 0 for every view of a plan with one placement.
std::vector<std::size_t> viewOrientations(const Plan& plan);
// Per setup of `plan` (its rest orientations, or the one placement): its views, those
// registered within it, and the frame they register in (PlannedOrientation::frame).
struct SetupRegistration {
  std::size_t views = 0;
  std::size_t registered = 0;
  std::size_t frame = 0;
};
std::vector<SetupRegistration> setupRegistration(const Plan& plan);
// The most views of `setups` registered in one frame: those of the setups it joins.
std::size_t registeredInOneFrame(const std::vector<SetupRegistration>& setups);

// Joins the setups of a plan over several rest orientations where markers stuck on the part
// (MarkerCarrier::Part), the same in every setup, register them (docs/registration.md):
// - reference points: the part's markers are known in one frame, so every setup with a
//   registered view that sees min_markers of them, not all within marker_spread of one
//   line, registers in it;
// - markers: two setups join where a registered view of each shares such markers.
// Overlap of scans across setups is not modelled: other methods join none. Sets each
// orientation's frame.
void joinSetups(Plan& plan, const RegistrationOptions& options);

// Setup `k` of a plan over several rest orientations, alone: its views with the
// registration, sequence and cell poses that are theirs, the samples in its world and
// measured by its views only; each view id less `id_offset`.
Plan setupPlan(const Plan& plan, std::size_t k, int id_offset = 0);
// What the plan adds to the ids of setup `k`'s views, which it planned numbered from 1 (and
// which seeded their simulated clouds and ICP): the count of views before them.
int setupIdOffset(const Plan& plan, std::size_t k);

// Where orientation `k` places the part (Plan::part_to_world for one placement).
Pose orientationPlacement(const Plan& plan, std::size_t k);

}  // namespace scanplan
