// The planner's pipeline (docs/planning.md): one placement of the part through the
// stages of stages.h, and the rest orientations of part.rest: all, merged.

#include "core/kd_tree.h"
#include "planning/stages.h"

#include <scanplan/cad/localization.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/planning/bridging.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/cell_poses.h>
#include <scanplan/planning/coverage_area.h>
#include <scanplan/planning/inspection.h>
#include <scanplan/planning/robot_steps.h>
#include <scanplan/robot/cycle.h>
#include <scanplan/robot/motion.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <set>

namespace scanplan {

SimulationOptions simulationOptionsFor(const ResolvedSpec& spec, const Pose& part_to_world,
                                       const std::vector<Marker>& markers) {
  SimulationOptions simulation;
  simulation.part_to_world = part_to_world;
  simulation.working_plane = spec.spec.working_plane;
  simulation.specular_faces = spec.specular;
  simulation.fixtures = fixturesInWorld(spec, part_to_world);
  for (const Marker& m : markers)
    if (m.on == MarkerCarrier::Part)
      simulation.covered.push_back({m.position, m.normal, spec.spec.marker_diameter / 2});
  return simulation;
}

SimulationOptions simulationOptionsFor(const ResolvedSpec& spec, const Part& part,
                                       const Pose& part_to_world) {
  return simulationOptionsFor(spec, part_to_world, specMarkers(spec, part, part_to_world));
}

std::vector<TriangleMesh> fixturesInWorld(const ResolvedSpec& spec, const Pose& part_to_world) {
  std::vector<TriangleMesh> meshes = spec.fixture_meshes;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const Pose placed = fixtureToWorld(spec.spec.fixtures[k], part_to_world);
    for (Vec3& v : meshes[k].vertices) v = placed * v;
  }
  return meshes;
}

// The most markers a grid may give around a part.
constexpr double kMostMarkers = 1e6;

namespace {

// The markers of the fixture models' CSVs, each given in its fixture's frame.
std::vector<Marker> fixtureMarkers(const Spec& spec, const Pose& part_to_world) {
  std::vector<Marker> markers;
  for (const FixtureModel& fixture : spec.fixtures) {
    if (fixture.markers_file.empty()) continue;
    const Pose placed = fixtureToWorld(fixture, part_to_world);
    for (Marker m : readMarkers(fixture.markers_file)) {
      m.position = placed * m.position;
      m.normal = placed.linear() * m.normal;
      markers.push_back(m);
    }
  }
  return markers;
}

// A grid of markers `step` mm apart: on the plate (or the rotary table) around the part
// (`margin` mm beyond it), on the part (as it stands, or in every rest orientation), on
// the fixtures.
struct MarkerGrid {
  double step = 0, margin = 0;
  bool on_plate = true, on_table = false, on_part = false, on_fixture = false;
  bool every_rest = false;
};

// The spec's marker grid.
MarkerGrid markerGridOf(const Spec& spec) {
  return {spec.marker_grid,      spec.marker_margin,   spec.markers_on_plate,
          spec.markers_on_table, spec.markers_on_part, spec.markers_on_fixture,
          spec.rest_all};
}

// Markers stuck on the part once for every rest orientation: the grid on the upward faces
// of each, in the part's frame, those within half a step of one kept before dropped; then
// placed by `part_to_world`. The same markers, in the same order, in every orientation.
std::vector<Marker> markersOnEveryRest(const Part& part, double step, const Pose& part_to_world) {
  std::vector<Marker> markers;
  for (const RestOrientation& rest : restOrientations(part)) {
    TriangleMesh world = part.mesh;
    for (Vec3& v : world.vertices) v = rest.part_to_world * v;
    const Pose back = rest.part_to_world.inverse();
    for (Marker m : markersOnPart(world, step)) {
      m.position = back * m.position;
      m.normal = back.linear() * m.normal;
      const bool near = std::any_of(markers.begin(), markers.end(), [&](const Marker& kept) {
        return (kept.position - m.position).norm() < step / 2;
      });
      if (!near) markers.push_back(m);
    }
  }
  for (Marker& m : markers) {
    m.position = part_to_world * m.position;
    m.normal = part_to_world.linear() * m.normal;
  }
  return markers;
}

// The markers of `grid` around the part placed by `part_to_world`; errors name `source`.
std::vector<Marker> gridMarkers(const MarkerGrid& grid, const ResolvedSpec& resolved,
                                const Part& part, const Pose& part_to_world) {
  TriangleMesh world = part.mesh;
  for (Vec3& v : world.vertices) v = part_to_world * v;
  Box box;
  for (const Vec3& v : world.vertices) box.add(v);
  // A marker per grid cell over the part and its margin: refused past kMostMarkers.
  const Vec3 size = box.empty() ? Vec3::Zero() : box.size();
  const double cells =
      (size.x() + 2 * grid.margin) / grid.step * ((size.y() + 2 * grid.margin) / grid.step);
  if (!(cells <= kMostMarkers))
    throw InputError(resolved.spec.source,
                     fmt::format("markers: a grid of {:g} mm with a margin of {:g} mm gives more "
                                 "than a million markers around this part",
                                 grid.step, grid.margin));
  std::vector<Marker> markers;
  if (grid.on_part)
    markers = grid.every_rest ? markersOnEveryRest(part, grid.step, part_to_world)
                              : markersOnPart(world, grid.step);
  if (grid.on_plate || grid.on_table)
    for (Marker m : markerGrid(box, grid.step, grid.margin)) {
      m.on = grid.on_table ? MarkerCarrier::Table : MarkerCarrier::Plane;
      markers.push_back(m);
    }
  if (grid.on_fixture)
    for (const TriangleMesh& fixture : fixturesInWorld(resolved, part_to_world))
      for (Marker m : markersOnPart(fixture, grid.step)) {
        m.on = MarkerCarrier::Plane;
        m.face = 0;
        markers.push_back(m);
      }
  return markers;
}

}  // namespace

std::vector<Marker> specMarkers(const ResolvedSpec& resolved, const Part& part,
                                const Pose& part_to_world) {
  const Spec& spec = resolved.spec;
  std::vector<Marker> markers;
  if (!spec.markers_file.empty()) {
    // Markers on the part are given in its frame, and placed with it.
    markers = readMarkers(spec.markers_file);
    const bool on_part = spec.markers_file_on == MarkerCarrier::Part;
    for (Marker& m : markers) {
      m.on = spec.markers_file_on;
      if (!on_part) continue;
      m.position = part_to_world * m.position;
      m.normal = part_to_world.linear() * m.normal;
    }
  } else if (spec.marker_grid > 0)
    markers = gridMarkers(markerGridOf(spec), resolved, part, part_to_world);
  const std::vector<Marker> on_fixtures = fixtureMarkers(spec, part_to_world);
  markers.insert(markers.end(), on_fixtures.begin(), on_fixtures.end());
  markers.insert(markers.end(), spec.placed_markers.begin(), spec.placed_markers.end());
  return markers;
}

Pose restingPlacement(const Part& part) {
  Pose placement = Pose::Identity();
  placement.translation() = Vec3(0, 0, -part.bounds().min.z());
  return placement;
}

Pose placementFor(const Part& part, const Spec& spec) {
  if (spec.rest_pose) return *spec.rest_pose;
  if (spec.rest_face) return restOnFace(part, spec.rest_face, spec.source).part_to_world;
  if (spec.rest_auto || spec.rest_all) return restOrientations(part).front().part_to_world;
  return restingPlacement(part);
}

namespace detail {

namespace {

// Per sample of `unmeasured` (indices), the furthest the pool's poses aimed nearest to it
// (the 64 whose targets are closest, within reach) got in the measurement test: the latest
// Loss, OutsideVolume when none has it in reach.
std::vector<Loss> bestLosses(const Placement& at, const MeasuredViews& pool,
                             const std::vector<std::size_t>& unmeasured) {
  std::vector<Loss> best(unmeasured.size(), Loss::OutsideVolume);
  if (pool.views.empty() || unmeasured.empty()) return best;
  const double reach = at.scanner().reach();
  std::vector<Vec3> targets;
  for (const View& view : pool.views) targets.push_back(view.target);
  const PointCloudAdaptor cloud{targets};
  PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  constexpr std::size_t kNearest = 64;
  std::vector<View> views;
  std::vector<SurfacePoint> points;
  std::vector<std::size_t> owner;
  std::vector<unsigned> nearest(kNearest);
  std::vector<double> distances(kNearest);
  for (std::size_t k = 0; k < unmeasured.size(); ++k) {
    const SurfacePoint& point = at.points[unmeasured[k]];
    const std::size_t found =
        tree.knnSearch(point.position.data(), kNearest, nearest.data(), distances.data());
    for (std::size_t n = 0; n < found; ++n) {
      if (distances[n] > reach * reach) continue;
      views.push_back(pool.views[nearest[n]]);
      points.push_back(point);
      owner.push_back(k);
    }
  }
  const std::vector<Loss> losses = at.simulator.measurePairs(views, points);
  for (std::size_t p = 0; p < losses.size(); ++p)
    if (losses[p] > best[owner[p]]) best[owner[p]] = losses[p];
  return best;
}

}  // namespace

void explainUncoverable(const Placement& at, const std::vector<Visibility>& visibility,
                        const MeasuredViews& pool, std::vector<PlannedSample>& samples) {
  // Below a coverage target of 1, a sample a pose of the pool measures was left out by the
  // target, and is coverable: it gets no reason.
  std::vector<char> left_out(samples.size(), 0);
  if (!at.settings().everySample())
    for (const std::vector<int>& measured : pool.samples)
      for (int i : measured) left_out[i] = 1;
  std::vector<std::size_t> unmeasured;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].measured_by.empty() && !at.isDone(i) && !left_out[i]) unmeasured.push_back(i);
  const std::vector<Loss> best = bestLosses(at, pool, unmeasured);
  for (std::size_t k = 0; k < unmeasured.size(); ++k) {
    const std::size_t i = unmeasured[k];
    PlannedSample& s = samples[i];
    s.last_loss = best[k];
    s.uncoverable = visibility[i] == Visibility::BelowWorkingPlane ? Uncoverable::BelowWorkingPlane
                    : visibility[i] == Visibility::OccludedByPart  ? Uncoverable::OccludedByPart
                    : best[k] == Loss::OutsideVolume               ? Uncoverable::NoValidPose
                                                                   : Uncoverable::Lost;
  }
  if (!at.cell.cell) return;
  // Not measured because of the robot, when poses clear of the part measure it.
  std::vector<std::size_t> unposed;
  std::vector<SurfacePoint> points;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].uncoverable == Uncoverable::NoValidPose ||
        samples[i].uncoverable == Uncoverable::Lost) {
      unposed.push_back(i);
      points.push_back(at.points[i]);
    }
  const std::vector<char> coverable = coverableByDenseCandidates(
      at.simulator, points, at.settings().vm_step * 2, at.settings().rotations);
  for (std::size_t k = 0; k < unposed.size(); ++k)
    if (coverable[k]) samples[unposed[k]].uncoverable = Uncoverable::Unreachable;
}

}  // namespace detail

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The times of a plan's stages: each lap closes the stage that ran since the last one.
class StageClock {
 public:
  explicit StageClock(Plan& plan) : plan_(plan) {}
  // A stage that runs again (another round of selection) adds to its time.
  void lap(const std::string& stage) {
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - stage_start_).count();
    const auto same = std::find_if(plan_.times.begin(), plan_.times.end(),
                                   [&](const StageTime& t) { return t.stage == stage; });
    if (same != plan_.times.end())
      same->seconds += seconds;
    else
      plan_.times.push_back({stage, seconds});
    stage_start_ = now;
  }
  double total() const { return secondsSince(start_); }

 private:
  Plan& plan_;
  Clock::time_point start_ = Clock::now(), stage_start_ = start_;
};

// The plan of a placement before its views: the part, the scanner, the samples in the
// world.
Plan placedPlan(const Part& part, const ResolvedSpec& spec, const std::vector<Sample>& sampled,
                const Pose& part_to_world) {
  Plan plan;
  plan.part_file = part.file;
  plan.part_faces = part.faces.size();
  plan.fixture_faces = spec.fixtureFaces();
  plan.part_to_world = part_to_world;
  plan.scanner = spec.spec.scanner;
  for (const Sample& s : sampled) {
    PlannedSample planned;
    planned.sample = s;
    planned.sample.position = part_to_world * s.position;
    planned.sample.normal = part_to_world.linear() * s.normal;
    planned.sample.tangent = part_to_world.linear() * s.tangent;
    plan.samples.push_back(planned);
  }
  return plan;
}

// The markers the selection keeps views registering by (none: by their geometry alone);
// nothing when it need not: registration off, or a robot that registers every view.
std::optional<std::vector<Marker>> registeringMarkers(const detail::Placement& at,
                                                      bool registration) {
  const RegistrationOptions& options = at.spec.spec.registration;
  if (!registration || robotRegistersAll(options)) return std::nullopt;
  if (options.method == RegistrationMode::Geometry) return std::vector<Marker>{};
  return at.markers;
}

// The candidates off the faces the plan samples: on the plate, on fixtures, on faces of the
// part that are no target.
std::vector<Marker> offTargets(const std::vector<Marker>& candidates, const Plan& plan) {
  std::set<int> targets;
  for (const PlannedSample& s : plan.samples) targets.insert(s.sample.face);
  std::vector<Marker> off;
  std::copy_if(candidates.begin(), candidates.end(), std::back_inserter(off), [&](const Marker& m) {
    return m.on != MarkerCarrier::Part || !targets.count(m.face);
  });
  return off;
}

// Candidates on the part three times closer than `step` where the views the proposal
// does not serve see them: views into narrow slots and bores see too few of the others.
std::vector<Marker> closerCandidates(const detail::Placement& at, const Plan& plan, double step) {
  std::vector<View> unserved;
  for (const View& view : plan.views)
    if (std::count(plan.proposed_markers->unserved.begin(), plan.proposed_markers->unserved.end(),
                   view.id))
      unserved.push_back(view);
  const std::vector<SurfacePoint> points = at.simulator.surfacePoints(step / 3, 2);
  std::vector<char> seen(points.size(), 0);
  for (const std::vector<int>& by_view : measuredPoints(at.simulator, unserved, points))
    for (int i : by_view) seen[i] = 1;
  std::vector<Marker> closer;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (seen[i])
      closer.push_back({points[i].position, points[i].normal, MarkerCarrier::Part, points[i].face});
  return closer;
}

// Markers proposed for the views of `plan` that register to nothing, among candidates
// spread over the whole surface of the part (one per step² of area on average), on the
// upward faces of the fixture models and on the plate around the part, a fifteenth of the
// field of view apart (or as far as a million candidates need); none when every view
// registers or the robot alone registers them. Markers on the part hide the surface they
// cover, so the candidates off the target faces are tried first; those on them are
// proposed only when they serve more views; and for the views still unserved, candidates
// three times closer where they look.
void proposeMarkers(const detail::Placement& at, Plan& plan) {
  const RegistrationOptions options = registrationOptions(at.spec.spec);
  if (plan.registration->registered() == plan.views.size() || robotRegistersAll(options)) return;
  // A grid on plate and fixtures a fifteenth of the field of view apart, coarser on parts
  // too large for that many candidates, and as many on the part's surface.
  const Spec& spec = at.spec.spec;
  MarkerGrid grid = markerGridOf(spec);
  const double across = at.part.bounds().size().maxCoeff() + 2 * grid.margin;
  grid.step = std::max(at.scanner().fov_height / 15, 1.01 * across / std::sqrt(kMostMarkers));
  grid.on_plate = true;
  grid.on_part = grid.on_table = grid.every_rest = false;
  grid.on_fixture = !spec.fixtures.empty();
  std::vector<Marker> candidates;
  for (const SurfacePoint& p : at.simulator.surfacePoints(grid.step))
    candidates.push_back({p.position, p.normal, MarkerCarrier::Part, p.face});
  for (const Marker& m : gridMarkers(grid, at.spec, at.part, plan.part_to_world))
    candidates.push_back(m);
  const auto propose = [&](const std::vector<Marker>& among) {
    return scanplan::proposeMarkers(at.simulator, plan.views, *plan.registration, among,
                                    plan.markers, options);
  };
  const std::vector<Marker> off = offTargets(candidates, plan);
  plan.proposed_markers = propose(off);
  const auto keepIfMore = [&](MarkerProposal other) {
    if (other.views > plan.proposed_markers->views) plan.proposed_markers = std::move(other);
  };
  if (off.size() != candidates.size()) keepIfMore(propose(candidates));
  if (plan.proposed_markers->unserved.empty()) return;
  for (const Marker& m : closerCandidates(at, plan, grid.step)) candidates.push_back(m);
  keepIfMore(propose(candidates));
}

// Orders the views of a plan without a cell by the generic positioning's time (the
// scanner's shortest paths, mm, each a trapezoid at the cycle's speed and acceleration;
// lengths in mm), each after one it registers to by `registration` where it can be, and
// sets the plan's cycle along that order. The seconds between views.
Eigen::MatrixXd sequenceByGenericTime(const detail::Placement& at, Plan& plan,
                                      const Registration& registration) {
  const CycleSettings& settings = at.spec.spec.cycle;
  const Eigen::MatrixXd paths = shortestPaths(directCosts(at.simulator, plan.views));
  const Eigen::MatrixXd times = paths.unaryExpr(
      [&](double mm) { return trapezoidSeconds(mm, settings.speed, settings.acceleration); });
  plan.sequence = sequenceViews(times, paths, plan.views, registration);
  std::map<int, Eigen::Index> index;
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    index[plan.views[v].id] = static_cast<Eigen::Index>(v);
  std::vector<double> moves;
  const std::vector<int>& order = plan.sequence->views;
  for (std::size_t k = 1; k < order.size(); ++k)
    moves.push_back(paths(index[order[k - 1]], index[order[k]]));
  plan.cycle = genericCycle(moves, plan.views.size(), at.scanner(), settings);
  return times;
}

// The final views' cell solutions (with a cell) and the seconds of the moves between
// them (shortest paths) by which they were ordered.
struct Sequenced {
  CellSolutions solutions;
  Eigen::MatrixXd times;
};

// Orders the plan's views, each after one it registers to by `registration` where it can
// be: by the robot's joint travel with a cell, whose solutions for the views it returns,
// else by the generic positioning.
Sequenced sequence(const detail::Placement& at, Plan& plan, const Registration& registration,
                   StageClock& clock, const Progress& progress) {
  report(progress, "sequencing " + std::to_string(plan.views.size()) + " views", 0);
  Sequenced sequenced;
  if (at.cell.cell) {
    // In joint space: the order by the robot's travel time, lengths in mm as always.
    sequenced.solutions = cellSolutions(*at.cell.cell, plan.views, at.cell.collisions);
    sequenced.times = shortestPaths(jointTravelTimes(*at.cell.cell, sequenced.solutions));
    plan.sequence =
        sequenceViews(sequenced.times, shortestPaths(directCosts(at.simulator, plan.views)),
                      plan.views, registration);
  } else {
    sequenced.times = sequenceByGenericTime(at, plan, registration);
  }
  clock.lap("sequencing");
  return sequenced;
}

// How registration sees the cell's rotary table: each view at the table angle nearest 0
// that reaches it (as the cell takes it); none without a table or without markers on the
// working plane.
std::shared_ptr<const TableTurn> markerTable(const CellCheck& cell,
                                             const std::vector<Marker>& markers) {
  if (!cell.cell || !cell.cell->table) return nullptr;
  return tableTurnFor(cell.cell->table->origin, cell.cell->table->axis, markers,
                      [cell](const View& view) {
                        const CellReach reach = reachView(*cell.cell, view, {}, 0, cell.collisions);
                        return reach.reachable() ? reach.poses.front().table_angle : 0.0;
                      });
}

// Registers the plan's views, bridging where they fall apart (bridging views measure
// samples too), and orders them (sequence).
Sequenced registerAndSequence(const detail::Placement& at, Plan& plan, StageClock& clock,
                              const Progress& progress) {
  plan.markers = at.markers;
  const std::size_t planned = plan.views.size();
  RegistrationOptions options = registrationOptions(at.spec.spec);
  options.table = markerTable(at.cell, plan.markers);
  plan.registration =
      registerWithBridging(at.simulator, plan.views, plan.markers, options, at.cell, progress);
  proposeMarkers(at, plan);
  const auto bridges = std::span<const View>(plan.views).subspan(planned);
  const auto measured = measuredPoints(at.simulator, bridges, at.points);
  for (std::size_t b = 0; b < bridges.size(); ++b)
    for (int i : measured[b]) plan.samples[i].measured_by.push_back(bridges[b].id);
  clock.lap("registration");
  return sequence(at, plan, *plan.registration, clock, progress);
}

// What the views are chosen from, besides the pool: the first `pinned` poses, always kept;
// the markers views are kept registering by (none: registration need not be kept); per
// pose, whether it registers by the markers alone; each sample's visibility.
struct Choice {
  std::size_t pinned;
  bool registration;
  const std::optional<std::vector<Marker>>& registering;
  const std::vector<char>& framed;
  const std::vector<Visibility>& visibility;
};

// Selects the plan's views from `pool`, registers and orders them, and moves the cell's
// robot through them. The pool indices of the views selected.
std::vector<std::size_t> selectAndMove(const detail::Placement& at,
                                       const detail::MeasuredViews& pool, const Choice& choice,
                                       Plan& plan, StageClock& clock, const Progress& progress) {
  report(progress, "selecting among " + std::to_string(pool.size()) + " poses", 0);
  const detail::Selection selection = detail::selectViews(
      at, pool, choice.pinned, plan.samples, choice.registering, choice.framed, progress);
  detail::applySelection(pool, selection.views, plan);
  plan.bound = selection.bound;
  clock.lap("selection");

  // Without registration, the views are ordered all the same, none bound to follow another.
  Sequenced sequenced = choice.registration ? registerAndSequence(at, plan, clock, progress)
                                            : sequence(at, plan, Registration{}, clock, progress);
  CellSolutions& solutions = sequenced.solutions;
  detail::explainUncoverable(at, choice.visibility, pool, plan.samples);
  clock.lap("not coverable");
  if (at.cell.cell) {
    const Cell& cell = *at.cell.cell;
    plan.cell = cell;
    if (solutions.size() != plan.views.size())  // not sequenced in joint space
      solutions = cellSolutions(cell, plan.views, at.cell.collisions);
    plan.cell_poses = cellPoses(cell, plan.views, visitingOrder(plan), solutions);
    report(progress, "robot motion", 0);
    const RobotProgram program =
        safeProgram(plan, cell, *at.cell.collisions, plan.cell_poses, "plan", "");
    takeProgramPoses(program, plan);
    plan.cycle = programCycle(program, at.scanner(), at.spec.spec.cycle);
    plan.cell_motion = CellMotion{plan.cycle->motion + plan.cycle->table, program.uncleared};
    clock.lap("robot motion");
  }
  if (plan.cycle && sequenced.times.rows() == static_cast<Eigen::Index>(plan.views.size()))
    plan.cycle->by_views =
        cycleByViews(insertionPathLengths(sequenced.times), at.scanner(), at.spec.spec.cycle);
  return selection.views;
}

// Rounds of selection after the first that leave out the poses behind moves the cell
// could not clear.
constexpr int kClearingRounds = 2;

// The pool poses behind the moves the robot could not clear (viewsBehind), the plan's views
// being the pool's `selected`. The pinned views and views not of the pool (bridging views)
// are kept.
std::vector<std::size_t> blockedPoses(const std::vector<RobotMove>& uncleared,
                                      const std::vector<std::size_t>& selected,
                                      std::size_t pinned) {
  std::vector<std::size_t> result;
  for (const int id : viewsBehind(uncleared)) {
    const auto k = static_cast<std::size_t>(id - 1);
    if (k < selected.size() && selected[k] >= pinned) result.push_back(selected[k]);
  }
  return result;
}

// `candidates` with the dense poses aimed at anchor samples and the caller's own.
std::vector<View> withDensePoses(const detail::Placement& at, std::vector<View> candidates,
                                 const PlanningOptions& options, const Progress& progress) {
  const std::vector<View> dense = detail::densePool(at, progress);
  candidates.insert(candidates.end(), dense.begin(), dense.end());
  candidates.insert(candidates.end(), options.candidates.begin(), options.candidates.end());
  return candidates;
}

// Per pose of `pool`, whether it registers by the `registering` markers by itself, with the
// poses shifted towards them added to the pool; the selection prices poses by it under
// reference points only (empty otherwise).
std::vector<char> framedPoses(const detail::Placement& at, detail::MeasuredViews& pool,
                              const std::optional<std::vector<Marker>>& registering,
                              const Progress& progress) {
  if (!registering) return {};
  std::vector<char> framed = detail::addMarkerShifts(at, pool, *registering, progress);
  if (registrationOptions(at.spec.spec).method != RegistrationMode::ReferencePoints) return {};
  return detail::addFramedPoses(at, pool, *registering, std::move(framed), progress);
}

// The plan's views chosen from `pool` (selectAndMove); in a cell, chosen again without the
// poses behind moves the robot could not clear, up to kClearingRounds more times.
void selectInRounds(const detail::Placement& at, detail::MeasuredViews& pool, const Choice& choice,
                    Plan& plan, StageClock& clock, const Progress& progress) {
  // The plan before its views, to choose them again from: in a cell only.
  const std::optional<Plan> unselected = at.cell.cell ? std::optional<Plan>(plan) : std::nullopt;
  for (int round = 0;; ++round) {
    const std::vector<std::size_t> selected =
        selectAndMove(at, pool, choice, plan, clock, progress);
    if (!unselected || round == kClearingRounds) break;
    const std::vector<std::size_t> blocked =
        blockedPoses(plan.cell_motion->uncleared, selected, choice.pinned);
    if (blocked.empty()) break;
    // Those poses taken out of the pool, the views are chosen again.
    for (std::size_t v : blocked) pool.samples[v].clear();
    report(progress,
           "selecting again without " + std::to_string(blocked.size()) +
               (blocked.size() == 1 ? " pose" : " poses") + " the robot cannot move clear to",
           0);
    std::vector<StageTime> times = std::move(plan.times);
    plan = *unselected;
    plan.times = std::move(times);
  }
}

// Plans the views for `sampled` (part frame) with the part placed by `part_to_world`;
// samples marked in `done` (measured in another placement) are not aimed at and count as
// covered in the selection.
Plan planPlacement(const Part& part, const ResolvedSpec& spec, const std::vector<Sample>& sampled,
                   const Pose& part_to_world, const std::vector<char>& done,
                   const PlanningOptions& options, const Progress& progress) {
  Plan plan = placedPlan(part, spec, sampled, part_to_world);
  StageClock clock(plan);
  report(progress, "building the scene", 0);
  std::vector<Marker> markers = specMarkers(spec, part, part_to_world);
  const Simulator simulator(part, spec.spec.scanner,
                            simulationOptionsFor(spec, part_to_world, markers));
  const std::optional<Cell>& cell = spec.spec.cell;
  std::unique_ptr<const CellCollisions> collisions;
  if (cell)
    collisions = std::make_unique<const CellCollisions>(
        *cell, spec.spec.scanner.body(), part.mesh, part_to_world, simulator.options().fixtures,
        simulator.options().working_plane, cell->clearance);
  const CellCheck cell_check{cell ? &*cell : nullptr, collisions.get()};
  const detail::Placement at{
      part, spec, simulator, cell_check, plan.samplePoints(), done, std::move(markers)};
  clock.lap("scene");

  detail::MeasuredViews added;
  std::vector<View> candidates;  // every other valid pose evaluated on the way
  plan.sweeps = detail::sweepViews(at, plan.samples, added, candidates, progress);
  std::size_t pinned = 0;  // the surface task's sweep views, always kept
  for (const Sweep& sweep : plan.sweeps)
    if (sweep.task == TaskType::Surface) pinned += sweep.views.size();
  clock.lap("sweeps");
  const std::vector<Visibility> visibility =
      detail::addViews(at, plan.samples, added, candidates, progress);
  clock.lap("view planning");
  report(progress, "aiming at the samples left", 0);
  detail::rescueViews(at, plan.samples, added);
  clock.lap("rescue");
  detail::MeasuredViews pool = detail::candidatePool(
      at, std::move(added), withDensePoses(at, std::move(candidates), options, progress), progress);
  const auto registering = registeringMarkers(at, options.registration);
  const std::vector<char> framed = framedPoses(at, pool, registering, progress);
  clock.lap("candidate pool");
  selectInRounds(at, pool, {pinned, options.registration, registering, framed, visibility}, plan,
                 clock, progress);
  plan.seconds = clock.total();
  return plan;
}

// Adds the robot program of a later orientation, its view ids shifted by `offset`, to
// `merged`'s: one program per orientation, run one after the other.
void appendMotion(Plan& merged, const CellMotion& motion, int offset) {
  CellMotion& sum = merged.cell_motion ? *merged.cell_motion : merged.cell_motion.emplace();
  sum.seconds += motion.seconds;
  for (RobotMove move : motion.uncleared) {
    if (move.from > 0) move.from += offset;
    if (move.to > 0) move.to += offset;
    sum.uncleared.push_back(move);
  }
}

// Appends `part` (planned in a later rest orientation) to `merged`: its views, registration,
// sequence and sweeps with ids shifted past merged's, and the samples it measures; its run
// after the part is turned over by hand (`turn_over` seconds), where merged has views.
void mergeOrientation(Plan& merged, Plan part, const RestOrientation& rest, double turn_over) {
  const int offset = static_cast<int>(merged.views.size());
  auto shift = [&](int& id) {
    if (id > 0) id += offset;
  };
  PlannedOrientation orientation;
  orientation.rest = rest;
  orientation.markers = part.markers;
  for (View& view : part.views) {
    shift(view.id);
    orientation.views.push_back(view.id);
    merged.views.push_back(view);
  }
  if (part.registration) {
    const int reference = part.registration->reference;
    orientation.reference = reference > 0 ? reference + offset : 0;
  }
  appendOrientation(merged, part, offset);
  if (part.proposed_markers) {
    if (!merged.proposed_markers) merged.proposed_markers.emplace();
    merged.proposed_markers->append(*part.proposed_markers);
  }
  if (part.bound) {
    PlanBound& sum = merged.bound ? *merged.bound : merged.bound.emplace();
    sum.views += part.bound->views;
    sum.greedy_views += part.bound->greedy_views;
    sum.lower_bound += part.bound->lower_bound;
    sum.pool += part.bound->pool;
    sum.proven_optimal = sum.lower_bound >= static_cast<double>(sum.views);
    sum.time_capped = sum.time_capped || part.bound->time_capped;
  }
  merged.cell = part.cell;
  merged.cell_poses.insert(merged.cell_poses.end(), part.cell_poses.begin(), part.cell_poses.end());
  if (part.cell_motion) appendMotion(merged, *part.cell_motion, offset);
  if (part.cycle && !merged.cycle) {
    merged.cycle = part.cycle;
  } else if (part.cycle) {
    if (merged.cycle->views > 0) {  // the part turned over by hand since the last setup
      ++merged.cycle->turns;
      merged.cycle->turning += turn_over;
    }
    *merged.cycle += *part.cycle;
  }
  for (Sweep& sweep : part.sweeps) {
    for (int& id : sweep.views) shift(id);
    merged.sweeps.push_back(std::move(sweep));
  }
  for (std::size_t i = 0; i < merged.samples.size(); ++i) {
    PlannedSample& s = merged.samples[i];
    // Still not measured: the reason found in the latest orientation.
    s.uncoverable = s.measured_by.empty() ? part.samples[i].uncoverable : Uncoverable::None;
    s.last_loss = part.samples[i].last_loss;
  }
  for (const StageTime& t : part.times) {
    auto same = std::find_if(merged.times.begin(), merged.times.end(),
                             [&](const StageTime& m) { return m.stage == t.stage; });
    if (same == merged.times.end())
      merged.times.push_back(t);
    else
      same->seconds += t.seconds;
  }
  merged.orientations.push_back(std::move(orientation));
}

// Every rest orientation in turn, steadiest first, each aiming at what the earlier ones
// left unmeasured; an orientation that adds no view is left out (but the first).
// Per sample, whether a marker stuck on the part covers it: so in every rest, since such
// markers turn with the part (specMarkers), and no view measures it.
std::vector<char> underPartMarkers(const Part& part, const ResolvedSpec& spec,
                                   const std::vector<Sample>& sampled, const Pose& part_to_world) {
  std::vector<SurfacePoint> points;
  for (const Sample& s : sampled)
    points.push_back({part_to_world * s.position, part_to_world.linear() * s.normal, s.face});
  return underSpots(simulationOptionsFor(spec, part, part_to_world).covered, points);
}

Plan planEveryRest(const Part& part, const ResolvedSpec& spec, const std::vector<Sample>& sampled,
                   const PlanningOptions& options, const Progress& progress) {
  const std::vector<RestOrientation> rests = restOrientations(part);
  Plan merged;
  std::vector<char> done(sampled.size(), 0);
  // The rests are tried until every sample is measured, or under a marker.
  const std::vector<char> covered =
      rests.empty() ? std::vector<char>(sampled.size(), 0)
                    : underPartMarkers(part, spec, sampled, rests.front().part_to_world);
  for (std::size_t k = 0; k < rests.size(); ++k) {
    bool left = false;
    for (std::size_t i = 0; i < done.size() && !left; ++i) left = !done[i] && !covered[i];
    if (k > 0 && !left) break;
    report(progress,
           "rest orientation " + std::to_string(k + 1) + " of " + std::to_string(rests.size()), 0);
    Plan plan = planPlacement(part, spec, sampled, rests[k].part_to_world, done, options, progress);
    if (k > 0 && plan.views.empty()) continue;
    for (std::size_t i = 0; i < plan.samples.size(); ++i)
      done[i] = done[i] || !plan.samples[i].measured_by.empty();
    if (k == 0) {
      merged = plan;
      merged.views.clear();
      merged.cell_poses.clear();
      merged.cell_motion.reset();
      merged.cycle.reset();
      merged.sweeps.clear();
      merged.times.clear();
      merged.bound.reset();
      for (PlannedSample& s : merged.samples) s.measured_by.clear();
      if (plan.registration) merged.registration = Registration{};
      if (plan.sequence) merged.sequence = Sequence{};
    }
    mergeOrientation(merged, std::move(plan), rests[k], spec.spec.cycle.turn_over);
  }
  // A sample under a marker in every rest is lost under it, whatever the first rest said.
  for (std::size_t i = 0; i < merged.samples.size() && i < covered.size(); ++i)
    if (covered[i] && merged.samples[i].measured_by.empty()) {
      merged.samples[i].uncoverable = Uncoverable::Lost;
      merged.samples[i].last_loss = Loss::UnderMarker;
    }
  joinSetups(merged, registrationOptions(spec.spec));
  return merged;
}

}  // namespace

namespace {

// Names the file of each sweep's patch, beside plan.json: patch-K.step for the K-th sweep.
void namePatchFiles(Plan& plan) {
  for (std::size_t k = 0; k < plan.sweeps.size(); ++k)
    if (plan.sweeps[k].patch)
      plan.sweeps[k].patch_file = "patch-" + std::to_string(k + 1) + ".step";
}

// The virtual inspection's U and bias of each characteristic it evaluates, beside the
// capability's prediction (planner.aim characteristics).
void checkByInspection(const Part& part, const ResolvedSpec& spec, Plan& plan,
                       const Progress& progress) {
  if (std::none_of(plan.characteristics.begin(), plan.characteristics.end(),
                   [&](const Characteristic& c) { return verifiable(part.gdt, c); }))
    return;
  InspectionOptions options;
  options.seed = spec.spec.planner.seed;
  const Inspection inspection = inspectPlan(part, spec, plan, options, progress);
  for (const InspectedCharacteristic& i : inspection.characteristics)
    for (Capability& k : plan.capabilities)
      if (k.characteristic == i.characteristic && i.evaluated) {
        k.inspected_uncertainty = i.uncertainty;
        k.inspected_bias = i.bias;
        k.inspected_precision = i.precision;
      }
}

// `spec` with, under planner.aim characteristics, the faces the part's characteristics are
// judged on as gdt targets, whatever its tasks sample.
Spec aimedSpec(const Part& part, Spec spec) {
  if (spec.planner.aim != Aim::Characteristics) return spec;
  Task targets{TaskType::Gdt, {}, {}, {}};
  for (int face : judgedFaces(part.gdt)) targets.faces.push_back({face, {}, {}});
  if (!targets.faces.empty()) spec.tasks.push_back(targets);
  return spec;
}

// The plan for `spec`, then the capability of its views for the part's characteristics.
Plan planAndJudge(const Part& part, const Spec& spec, const PlanningOptions& options,
                  const Progress& progress) {
  const auto start = Clock::now();
  report(progress, "sampling", 0);
  const ResolvedSpec resolved = resolveSpec(part, aimedSpec(part, spec));
  const std::vector<Sample> sampled =
      sampleTargets(part, resolved.targets, samplingOptionsFor(spec.scanner));
  if (sampled.empty())
    throw PlanningError(resolved.source, "the spec's tasks leave no sample to plan for");
  const StageTime sampling{"sampling", secondsSince(start)};
  Plan plan = spec.rest_all ? planEveryRest(part, resolved, sampled, options, progress)
                            : planPlacement(part, resolved, sampled, placementFor(part, spec), {},
                                            options, progress);
  plan.times.insert(plan.times.begin(), sampling);
  namePatchFiles(plan);
  const auto judged = Clock::now();
  report(progress, "measurement capability", 0);
  plan.characteristics = characteristics(part.gdt);
  CapabilityJudgement judged_plan = judgeCapability(part, resolved, plan, plan.characteristics);
  plan.capabilities = std::move(judged_plan.capabilities);
  plan.capable_by_views = std::move(judged_plan.by_views);
  plan.times.push_back({"capability", secondsSince(judged)});
  if (spec.planner.aim == Aim::Characteristics) {
    const auto inspected = Clock::now();
    checkByInspection(part, resolved, plan, progress);
    plan.times.push_back({"inspection", secondsSince(inspected)});
  }
  const auto area_start = Clock::now();
  report(progress, "measured area", 0);
  plan.face_areas = measuredArea(part, resolved, plan);
  plan.times.push_back({"measured area", secondsSince(area_start)});
  plan.seconds = secondsSince(start);
  return plan;
}

std::size_t capableCount(const Plan& plan) {
  return static_cast<std::size_t>(
      std::count_if(plan.capabilities.begin(), plan.capabilities.end(),
                    [](const Capability& k) { return k.verdict == Verdict::Capable; }));
}

// A characteristic mostly covered but not capable: more views on its faces may lift it.
bool liftable(const Plan& plan) {
  return std::any_of(plan.capabilities.begin(), plan.capabilities.end(), [](const Capability& k) {
    return (k.verdict == Verdict::Marginal || k.verdict == Verdict::NotCapable) &&
           k.reason != Shortfall::Uncovered;
  });
}

}  // namespace

namespace {

// A plan of more views than planner.most_views allows is refused, as a part is whose size
// would need them. \throw PlanningError naming the spec (else the part).
void checkMostViews(const Plan& plan, const Part& part, const Spec& spec) {
  if (plan.views.size() > static_cast<std::size_t>(spec.planner.most_views))
    throw PlanningError(spec.source.empty() ? part.file : spec.source,
                        fmt::format("the plan needs {} views, more than planner.most_views ({})",
                                    plan.views.size(), spec.planner.most_views));
}

// The spec as the plan records it: a file by its absolute path.
std::optional<PlanSpec> recordedSpec(const Spec& spec) {
  if (spec.text.empty() && spec.rest_given.empty()) return std::nullopt;
  std::error_code ec;
  const bool file = std::filesystem::is_regular_file(spec.source, ec);
  return PlanSpec{file ? std::filesystem::absolute(spec.source, ec).string() : spec.source,
                  spec.text, spec.rest_given};
}

}  // namespace

Plan planViews(const Part& part, const Spec& spec, const PlanningOptions& options,
               const Progress& progress) {
  Plan plan = planAndJudge(part, spec, options, progress);
  if (spec.planner.lift_capability && liftable(plan)) {
    // Again with every characteristic's faces as GD&T targets; kept when more are capable.
    Spec lifting = spec;
    Task targets{TaskType::Gdt, {}, {}, {}};
    for (const Characteristic& c : plan.characteristics)
      for (int face : c.faces) targets.faces.push_back({face, {}, {}});
    lifting.tasks.push_back(targets);
    Plan lifted = planAndJudge(part, lifting, options, progress);
    lifted.seconds += plan.seconds;
    plan.seconds = lifted.seconds;
    if (capableCount(lifted) > capableCount(plan)) plan = std::move(lifted);
  }
  checkMostViews(plan, part, spec);
  plan.spec = recordedSpec(spec);
  return plan;
}

PlacedMarkers planWithProposedMarkers(const Part& part, Spec spec, Plan plan,
                                      const PlanningOptions& options, const Progress& progress,
                                      int rounds) {
  if (!plan.orientations.empty())
    throw InputError(part.file, "--place-markers plans one rest orientation only");
  registerByPlacedMarkers(spec.registration);
  PlacedMarkers result{std::move(plan), {}};
  for (int round = 0; round < rounds; ++round) {
    const Plan& last = result.plan;
    if (!last.proposed_markers || last.proposed_markers->markers.empty() ||
        (last.registration && last.registration->registered() == last.views.size()))
      break;
    for (Marker m : last.proposed_markers->markers) {
      m.placed = true;
      result.placed.push_back(m);
    }
    spec.placed_markers = result.placed;
    PlanningOptions again = options;  // the views the markers were proposed for kept at hand
    again.candidates.insert(again.candidates.end(), last.views.begin(), last.views.end());
    result.plan = planViews(part, spec, again, progress);
  }
  return result;
}

}  // namespace scanplan
