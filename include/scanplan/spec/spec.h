#pragma once
// The inspection spec (docs/spec.md), YAML in millimetres and degrees. Every field has a
// default: an empty spec (or none) means one `global` task with the default scanner.

#include <scanplan/cad/part.h>
#include <scanplan/core/tasks.h>
#include <scanplan/core/view.h>
#include <scanplan/registration/registration.h>
#include <scanplan/robot/cell.h>
#include <scanplan/robot/cycle.h>
#include <scanplan/scanner/sensor.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

// One way to name faces in a spec: by id, by the name the file gives them, or by colour.
struct FaceSelector {
  int id = 0;                  // 1-based face id, or 0
  std::string name;            // face (or solid) name from the CAD file, or ""
  std::optional<Color> color;  // surface colour, matched within 1/255 per channel
};

struct Task {
  TaskType type = TaskType::Global;
  std::vector<FaceSelector> faces;   // target faces (gdt, trim, surface)
  std::string points_file;           // control points CSV (points), resolved to the spec's folder
  std::vector<ControlPoint> points;  // read from it
};

// A fixture model from its own file (`fixtures:`): a clamp, a frame or a table. It hides
// the part from camera and projector, the scanner and the robot stay clear of it, it is
// never sampled, and markers may be placed on it.
struct FixtureModel {
  std::string file;                   // STEP, IGES, BREP or a mesh, resolved to the spec's folder
  Pose placement = Pose::Identity();  // the fixture's frame in the part's (or the world's)
  bool in_world = false;              // frame: world: fixed in the cell, whatever the rest
  std::string markers_file;           // markers: a CSV in the fixture's frame, resolved, or ""
};

// How a characteristic's capability is judged (docs/capability.md).
struct CapabilityOptions {
  double capable_ratio = 4;   // capable from this tolerance width / (2 U) on (shops ask 10
                              // for gauges)
  double marginal_ratio = 1;  // marginal from this one on
  int draws = 200;            // Monte Carlo draws of the noise
  // The spacing at the standoff of the points a characteristic is read from, mm, each the
  // mean of the scanner's points around it (evaluationSpacing; 0: a hundredth of the
  // field's height).
  double evaluation_spacing = 0;
};

// planner.coverage (docs/planning.md, "Coverage targets"): the share of the coverable
// samples the selection must measure, for the priority samples and for each task's
// others. 1 everywhere: every sample a pose of the pool measures.
struct CoverageTargets {
  double priority = 1;               // the priority faces' samples
  double others = 1;                 // every task's other samples, unless named below
  std::map<TaskType, double> tasks;  // a task's own share

  double of(Role role, TaskType task) const;
  bool full() const;  // every share 1
};

// planner.objective (docs/planning.md, "Objective"): what a view of the selection costs.
enum class Objective {
  Views,     // one view, one unit: the fewest views
  CycleTime  // its seconds on the cell: acquisition, settling, handshake and a share of motion
};

// planner.aim (docs/planning.md, "Aim"): what the selection must measure.
enum class Aim {
  Samples,         // every coverable sample, to the coverage targets
  Characteristics  // what each characteristic's capability needs of its faces and its
                   // datums'; the other tasks' samples to their coverage targets
};

struct PlannerSettings {
  std::uint64_t seed = 1;  // k-means and any other randomness
  double vm_step = 5;      // visibility-map grid step, degrees
  double tilt_min = 30;    // preferred tilt of tilted positioning, degrees
  double tilt_max = 50;
  int max_failures = 3;            // attempts before a sample is declared not coverable
  double sweep_overlap = 0.3;      // share of the field of view neighbouring sweep tiles share
  int rotations = 8;               // rotations about the view axis tried per cluster direction
  double rescue_step = 10;         // rescue: directions on a grid of this step, degrees, ...
  int rescue_rotations = 8;        // ... each with this many rotations about the view axis
  bool rescue_narrow = false;      // ... and through narrow openings, more finely (adding.cpp)
  int anchors = 1200;              // pool: dense poses around at most this many anchor samples,
  int pool_rotations = 4;          // ... each with this many rotations about the view axis
  int selection_nodes = 10;        // the exact selection's branch-and-bound nodes (CBC)
  double selection_seconds = 120;  // a cap for safety, per placement: a plan it stops depends
                                   // on the machine, and says so (PlanBound::time_capped)
  int most_views = 10000;          // a part larger than this many fields of view is refused
  CapabilityOptions capability;    // capable_ratio: planner.capable_ratio
  bool lift_capability = false;    // plan again with the characteristics' faces as targets when
                                   // one is covered but not capable; kept if more are capable
  CoverageTargets coverage;        // below 1: the selection is a partial cover
  Objective objective = Objective::Views;
  Aim aim = Aim::Samples;

  // Whether the selection must measure every sample a pose of the pool measures.
  bool everySample() const { return aim == Aim::Samples && coverage.full(); }
};

struct Spec {
  std::string source;                  // the file it was read from, "" for defaults
  std::string text;                    // the text it was read from, "" for defaults
  std::string rest_given;              // part.rest as given over the text's (setRest), or ""
  Scanner scanner;                     // `scanner:` preset name or mapping
  std::string part_file;               // part.file, resolved to the spec's folder, or ""
  bool rest_auto = false;              // part.rest: auto (the steadiest rest orientation)
  bool rest_all = false;               // part.rest: all (plan every rest orientation, merged)
  int rest_face = 0;                   // part.rest: a face id to rest on (0: none)
  std::optional<Pose> rest_pose;       // part.rest: a 4x4 part-to-world matrix
                                       // (neither: the CAD orientation, lifted onto the plane)
  std::vector<FaceSelector> priority;  // roles.priority
  std::vector<FaceSelector> fixture;   // roles.fixture: faces that only occlude
  std::vector<FaceSelector> specular;  // roles.specular
  bool gdt_from_file = false;          // gdt: from-file (or all)
  bool gdt_dimensions = false;         // gdt: all: the dimensioned faces are targets too
  std::string markers_file;            // markers: a CSV (world frame), resolved, or ""
  MarkerCarrier markers_file_on = MarkerCarrier::Plane;  // markers: {file, on}
  double marker_grid = 0;              // markers: {grid: step, margin: mm, on: ...}: a
  double marker_margin = 100;          // generated grid (0: none) on the working plane
  bool markers_on_plate = true;        // around the part (or the same on the rotary
  bool markers_on_table = false;       // table), and/or on the part's upward faces
  bool markers_on_part = false;        // (every rest orientation's with part.rest: all),
  bool markers_on_fixture = false;     // and/or on the fixture models' upward faces
  double marker_diameter = 8;          // markers.diameter: the surface a marker on the part
                                       // covers, mm (docs/registration.md)
  std::vector<FixtureModel> fixtures;  // fixtures: models with their own files
  std::vector<Marker> placed_markers;  // world frame: added to the markers above (those a
                                       // plan proposed, placed: `plan --place-markers`)
  RegistrationOptions registration;    // registration: thresholds of the pair checks
  std::vector<Task> tasks;             // never empty: defaults to one global task
  PlannerSettings planner;
  bool working_plane = true;  // cell.working_plane: the plane z = 0 occludes
  std::optional<Cell> cell;   // cell.robot, cell.mount, cell.table: views must be reachable
  CycleSettings cycle;        // cycle: what a view takes besides its acquisition
};

// The default spec: the generic structured-light scanner, one global task.
Spec defaultSpec();

// How the part stands, given over the spec's part.rest (`plan --rest`): auto, all, drawn (as
// the CAD model is drawn) or a face id; kept in Spec::rest_given. \throw UsageError naming
// `key` for another value.
void setRest(Spec& spec, const std::string& rest, const std::string& key);

// A spec resolved against its part, once: every face selector turned into face ids and
// checked, the GD&T faces taken from the part. Every stage of planning reads this.
struct ResolvedSpec {
  Spec spec;
  std::string source;          // the spec's file, else the part's: where errors point
  Targets targets;             // what sampling targets
  std::vector<int> specular;   // roles.specular, sorted face ids
  std::vector<int> gdt_faces;  // with gdt: from-file, the part's GD&T faces, else empty
  std::vector<TriangleMesh> fixture_meshes;  // per spec.fixtures: its mesh, its own frame
  std::size_t fixture_model_faces = 0;       // faces of the fixture models' files
  std::vector<std::string> warnings;         // the fixture models' import warnings,
                                             // each "<file>: <warning>"

  // The fixture faces: roles.fixture's and those of the fixture models.
  std::size_t fixtureFaces() const { return targets.fixture.size() + fixture_model_faces; }
};

// Resolves `spec` against `part`, and reads its fixture models' files. A task given again
// (the same type and faces, or the same points file) is kept once.
// \throw InputError for faces or files the spec names wrongly, or gdt: from-file on a
// part without GD&T; PlanningError for a gdt, trim or surface task left without target
// faces.
ResolvedSpec resolveSpec(const Part& part, const Spec& spec);

// The registration's options as the spec sets them: its registration section, with the
// planner's seed.
RegistrationOptions registrationOptions(const Spec& spec);

// The registration of views with markers placed where a plan proposed them (`plan
// --place-markers`): by markers where `options` say geometry, else the markers go unused.
// The planner and the check of its plan take the same.
void registerByPlacedMarkers(RegistrationOptions& options);

// The files `spec` names: itself, its part, markers, fixture models and their markers, and
// control points; a run must not write over any of them.
std::vector<std::string> specFiles(const Spec& spec);

// Where a fixture model stands in the world, with the part placed by `part_to_world`.
Pose fixtureToWorld(const FixtureModel& fixture, const Pose& part_to_world);

// Faces of the part's GD&T: the faces of its characteristics (cad/gdt.h) and of its
// datums, sorted, unique; the dimensions' only with `dimensions`.
std::vector<int> gdtFaces(const Part& part, bool dimensions = false);

// The face ids that `selectors` name on `part`, sorted and unique.
// \throw InputError naming `source` and the selector that matches no face.
std::vector<int> resolveFaces(const Part& part, const std::vector<FaceSelector>& selectors,
                              const std::string& source);

}  // namespace scanplan
