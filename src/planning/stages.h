#pragma once
// The stages of planning one placement of the part, in the order planner.cpp runs them.
// Each takes what it only reads as const and extends or returns what it makes.

#include <scanplan/planning/planner.h>
#include <scanplan/scanner/visibility.h>

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace scanplan::detail {

// Views with the samples each measures (indices, ascending).
struct MeasuredViews {
  std::vector<View> views;
  std::vector<std::vector<int>> samples;

  std::size_t size() const { return views.size(); }
  void add(const View& view, std::vector<int> measured) {
    views.push_back(view);
    samples.push_back(std::move(measured));
  }
};

// What every stage of one placement reads.
struct Placement {
  const Part& part;
  const ResolvedSpec& spec;
  const Simulator& simulator;
  CellCheck cell;                    // the spec's cell, if any
  std::vector<SurfacePoint> points;  // the samples in the world, as simulation targets
  std::vector<char> done;            // per sample: measured in an earlier placement; or empty
  std::vector<Marker> markers = {};  // the spec's (specMarkers), world frame

  const Scanner& scanner() const { return simulator.scanner(); }
  const PlannerSettings& settings() const { return spec.spec.planner; }
  bool isDone(std::size_t i) const { return !done.empty() && done[i]; }
};

// The samples `view` measures, indices ascending (for many views at once, measuredPoints
// of simulation.h).
std::vector<int> measuredBy(const Simulator& simulator, const View& view,
                            std::span<const SurfacePoint> points);

// Adds `view`, which measures `measured`, to `added` with the next id, and that id to its
// samples' measured_by; nothing when it measures no sample. True when added.
bool addView(View view, std::vector<int> measured, std::vector<PlannedSample>& samples,
             MeasuredViews& added);

// The pose of a cluster (`members`, world frame): of the poses along its clusterDirections
// (poses.h), aimed at `mean_point`, the valid one measuring most members, the first on
// ties. Every valid pose tried is appended to `candidates`. `status` receives each
// member's Visibility.
std::optional<View> clusterPose(const Placement& at, const std::vector<Sample>& members,
                                const Vec3& mean_point, const Vec3& mean_normal, bool normal_only,
                                std::vector<Visibility>& status, std::vector<View>& candidates);

// Sweep positioning: one view per tile of each surface the samples ask to sweep, added
// first to `added`, those of the surface task (which must cover the surface, not only its
// samples) before the others. The sweeps with their views' indices in `added` plus one.
std::vector<Sweep> sweepViews(const Placement& at, std::vector<PlannedSample>& samples,
                              MeasuredViews& added, std::vector<View>& candidates,
                              const Progress& progress);

// Iterative adding: rounds of clustering the samples still pending and one pose per
// cluster, until a round adds nothing or no sample is pending (a sample is no longer
// pending after planner.max_failures views aimed at it missed it). Per sample, how its
// visibility map turned out.
std::vector<Visibility> addViews(const Placement& at, std::vector<PlannedSample>& samples,
                                 MeasuredViews& added, std::vector<View>& candidates,
                                 const Progress& progress);

// Rescue: each sample still unmeasured gets the first valid dense pose (planner.rescue)
// aimed at it alone that measures it.
void rescueViews(const Placement& at, std::vector<PlannedSample>& samples, MeasuredViews& added);

// The dense poses of the pool: valid poses in rings around up to planner.anchors anchor
// samples spread over the targets, planner.pool_rotations rotations each, and their
// normal poses shifted across the axis towards the neighbouring targets.
std::vector<View> densePool(const Placement& at, const Progress& progress);

// The candidate pool: the views added, then every other valid pose evaluated and the
// dense poses, each with the samples it measures.
MeasuredViews candidatePool(const Placement& at, MeasuredViews added,
                            const std::vector<View>& candidates, const Progress& progress);

// Target shift towards markers: each pose of the pool that measures samples but sees too
// few `markers` to register by, moved across its axis (up to half the field of view) by
// the least shift that takes in enough of them and keeps measuring its own samples (those
// within a quarter of the field of view of its target), is added to the pool so moved.
// Per pose of the pool then, whether it registers by the markers by itself (none without
// markers).
std::vector<char> addMarkerShifts(const Placement& at, MeasuredViews& pool,
                                  const std::vector<Marker>& markers, const Progress& progress);

// Framed poses, under registration by reference points: for each sample that poses of the
// pool measure but none that sees enough `markers` to register by, up to four valid poses
// that measure it and register by the markers (aimed at it from a 20-degree grid of
// directions, with the sample off the centre of the field), added to the pool with the
// samples each measures. Samples those measure need no search of their own. `framed`: per
// pose of the pool, whether it registers by the markers by itself (addMarkerShifts'); so
// extended to the poses added.
std::vector<char> addFramedPoses(const Placement& at, MeasuredViews& pool,
                                 const std::vector<Marker>& markers, std::vector<char> framed,
                                 const Progress& progress);

// What the coverage targets (planner.coverage) ask of the views after the `pinned` ones:
// per sample its group (0: the priority samples, 1 + a task type's place in kTaskTypes: that
// task's others; under planner.aim characteristics, the gdt task's samples in one group per
// face the characteristics are judged on, each needing kCoveredEnough of them), or -1 when
// it counts as measured already (done in an earlier placement, or by a pinned view), no view
// of the pool measures it, or nothing asks for it; per group the samples still to measure.
struct CoverageNeed {
  std::vector<int> group;
  std::vector<double> need;
};
CoverageNeed coverageNeed(const Placement& at, const MeasuredViews& pool, std::size_t pinned,
                          const std::vector<PlannedSample>& samples);

// What the selection aims at: the targets' need, and what each pose of the pool costs (all
// 1: the fewest views; planner.objective cycle_time: its estimated seconds).
struct SelectionAim {
  CoverageNeed needs;
  std::vector<double> costs;  // per pool index
};

// The views chosen from the pool (indices into it), and how close they are to the fewest.
struct Selection {
  std::vector<std::size_t> views;
  PlanBound bound;
};

// The selection over the pool, its `pinned` first views always kept: a greedy set cover by
// marginal coverage, priority samples first; improved by CBC on the pool's set cover of
// every sample some pool view measures (planner.selection_nodes, starting from the
// greedy cover); views whose samples all others also measure dropped (last first); the
// rest ordered by marginal coverage, priority samples first. Below coverage targets of 1,
// by cycle time (planner.objective), or aimed at characteristics (planner.aim), CBC solves
// the partial cover of the targets (coverageNeed) at the poses' costs instead. With
// `registering` (the markers views register by, none: by geometry alone), the
// connectedCover of the same targets and costs, unless no view of it registers to another;
// its bound is then the LP relaxation's. Under registration by reference points
// (`framed`: per pose, whether it registers by the markers by itself, as addFramedPoses
// gives it), the partial cover instead, each pose not framed costing twice its cost. The
// bound counts views.
// Progress shows the connectedCover's, or the share of its budget CBC has used.
Selection selectViews(const Placement& at, const MeasuredViews& pool, std::size_t pinned,
                      const std::vector<PlannedSample>& samples,
                      const std::optional<std::vector<Marker>>& registering,
                      const std::vector<char>& framed, const Progress& progress);

// The registration-aware cover of `aim`: views chosen one at a time, the `pinned` first
// pool views first, each the pose measuring most samples not yet covered per cost
// (priority first) among the poses that register to a view already chosen (the
// registration's pair test: `markers` they share, or an overlap constraining ICP); when
// none of them measures anything new, the best pose something could register to, then any
// pose; until every group has its need. Groups left apart are then joined to the largest
// through connector poses, each registering to a view of both. Chosen views whose samples
// others measure too and that no other registers to are dropped. On the cover kept, the
// groups still apart are joined through chains of poses, each registering to the one
// before (verified by ICP). Pool indices in the order chosen; none when no view registers
// to another. Progress shows the share of the samples the covers have covered on
// average, then the groups the chains were sought for.
std::vector<std::size_t> connectedCover(const Placement& at, const MeasuredViews& pool,
                                        std::size_t pinned,
                                        const std::vector<PlannedSample>& samples,
                                        const SelectionAim& aim, const std::vector<Marker>& markers,
                                        const Progress& progress);

// Which views of `chosen` (pool indices) are kept: each one, last first but for the first
// `pinned`, is dropped when every sample it measures is measured by another view still kept
// or by an earlier placement, unless `needed(k)` holds for it; `dropped(k)` hears of each
// drop (k indexes `chosen`).
std::vector<char> keptViews(const Placement& at, const MeasuredViews& pool,
                            const std::vector<std::size_t>& chosen, std::size_t pinned,
                            std::size_t samples,
                            const std::function<bool(std::size_t)>& needed = nullptr,
                            const std::function<void(std::size_t)>& dropped = nullptr);

// The selected views as the plan's, ids 1..n in selection order, the task of a candidate
// taken from most of the samples it measures; the samples' measured_by set to them; each
// sweep's views (pool indices + 1 on entry) the ids of those the selection kept.
void applySelection(const MeasuredViews& pool, const std::vector<std::size_t>& selected,
                    Plan& plan);

// Why each sample still unmeasured (no pose of the pool measures it) is not coverable:
// occluded from every direction of its visibility map (by the working plane, else by the
// part); else lost in simulation, its `last_loss` the furthest the 64 pool poses aimed
// nearest to it got in the measurement test (occluded when every one in reach was); else,
// none having it in reach, no valid pose. With a cell, a sample lost or without a valid
// pose is unreachable by the robot when poses clear of the part measure it.
void explainUncoverable(const Placement& at, const std::vector<Visibility>& visibility,
                        const MeasuredViews& pool, std::vector<PlannedSample>& samples);

}  // namespace scanplan::detail
