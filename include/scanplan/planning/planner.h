#pragma once
// View planning (docs/planning.md): from the resolved spec, samples and clusters; poses
// from their visibility maps, sweeps over wide surfaces, iterative adding until nothing
// more can be covered, a last pass aimed at single samples; the selection of the views by
// marginal coverage; then the registration check with bridging views, and the sequence.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/plan/plan.h>
#include <scanplan/planning/poses.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/spec/spec.h>

#include <vector>

namespace scanplan {

// How planViews runs, beyond what the spec sets (the spec's planner, registration and
// cell sections set everything else).
struct PlanningOptions {
  bool registration = true;  // check registration, bridge, and sequence the views
  // Poses added to the candidate pool, in the world of the placement planned (a plan of
  // one rest orientation): an earlier plan's views, so that the plan made again with the
  // markers proposed for them can keep them.
  std::vector<View> candidates = {};
};

// The simulation of the part placed by `part_to_world` as the spec sets it: working plane,
// specular faces, fixture models, and the surface its markers on the part cover.
SimulationOptions simulationOptionsFor(const ResolvedSpec& spec, const Part& part,
                                       const Pose& part_to_world);
// The same with the spec's markers (specMarkers) known already.
SimulationOptions simulationOptionsFor(const ResolvedSpec& spec, const Pose& part_to_world,
                                       const std::vector<Marker>& markers);

// The spec's fixture models in the world, with the part placed by `part_to_world`.
std::vector<TriangleMesh> fixturesInWorld(const ResolvedSpec& spec, const Pose& part_to_world);

// The spec's markers, world frame: its CSV, or its grid around the footprint of the part
// placed by `part_to_world`, on the part and/or on the fixture models; and the markers of
// the fixture models' own CSVs. None when it names none.
std::vector<Marker> specMarkers(const ResolvedSpec& spec, const Part& part,
                                const Pose& part_to_world);

// The part standing on the working plane as it lies in its CAD frame: lifted so that its
// lowest point is at z = 0 (rest orientations come with localization).
Pose restingPlacement(const Part& part);

// Where the spec puts the part: part.rest's matrix, the rest orientation on its face, the
// steadiest one (auto, and the first of all), else restingPlacement. \throw InputError
// for a rest face the part cannot stand on.
Pose placementFor(const Part& part, const Spec& spec);

// Plans the views for the spec's tasks, honouring the whole spec (scanner, roles,
// markers, registration, planner settings, cell); with part.rest: all, in every rest
// orientation in turn, steadiest first, each aiming at the samples the earlier ones left
// unmeasured. \throw PlanningError when the spec leaves nothing to plan (no samples, or
// all targets on fixture faces); InputError for a bad spec.
Plan planViews(const Part& part, const Spec& spec, const PlanningOptions& options = {},
               const Progress& progress = {});

// `plan` (of `part` by `spec`, one rest orientation) made again with the markers it
// proposed added to the spec's (Spec::placed_markers; a spec registering by geometry then
// registers by markers, else they would go unused), and again with those the new plan
// proposes, until every view registers, nothing more is proposed, or after `rounds` plans.
// The last plan, its placed_markers the markers added in all. \throw InputError for a plan
// over several rest orientations.
struct PlacedMarkers {
  Plan plan;
  std::vector<Marker> placed;
};
PlacedMarkers planWithProposedMarkers(const Part& part, Spec spec, Plan plan,
                                      const PlanningOptions& options = {},
                                      const Progress& progress = {}, int rounds = 3);

// Which samples some valid pose of a dense candidate set measures: the camera at the
// standoff from the sample itself, looking at it, from every direction of a `step`-degree
// grid within the camera's glancing cone, each with `rotations` rotations about the view
// axis, valid for `cell` (poses.h). The reference of coverage in benchmarks and reports;
// the planner's rescue pass aims at such poses too.
std::vector<char> coverableByDenseCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples,
                                             double step = 10, int rotations = 8,
                                             const CellCheck& cell = {});

// Which samples some valid pose of a wider dense set measures: the poses of
// coverableByDenseCandidates, each also moved so that the sample lies a quarter or 0.45 of
// the field off the centre each way and a quarter of the depth of field nearer or further.
// The planner's rescue pass tries 8 of its 74 places off the centre (docs/planning.md); so
// this reference of coverage reaches what the planner's candidates miss.
std::vector<char> coverableByWiderCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples,
                                             double step = 10, int rotations = 8,
                                             const CellCheck& cell = {});

// Which samples some valid pose of a wider dense set measures while it registers by
// reference points on `markers` by itself (`options.min_markers` seen, off one line): the
// poses of coverableByDenseCandidates, each also moved so that the sample lies a quarter or
// 0.45 of the field off the centre each way and a quarter of the depth of field nearer or
// further. The
// reference of what markers can frame in benchmarks: a sample it leaves out is measured by
// no view of that wider search that the markers register.
std::vector<char> framedByDenseCandidates(const Simulator& simulator,
                                          const std::vector<SurfacePoint>& samples,
                                          const std::vector<Marker>& markers,
                                          const RegistrationOptions& options, double step = 10,
                                          int rotations = 8, const CellCheck& cell = {});

}  // namespace scanplan
