#pragma once
// The stages of planning one placement of the part, in the order planner.cpp runs them.
// Each takes what it only reads as const and extends or returns what it makes.

#include <scanplan/planning/planner.h>
#include <scanplan/visibility.h>

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

  const Scanner& scanner() const { return simulator.scanner(); }
  const PlannerSettings& settings() const { return spec.spec.planner; }
  bool isDone(std::size_t i) const { return !done.empty() && done[i]; }
};

// The samples `view` measures, indices ascending; and the same for many views at once.
std::vector<int> measuredBy(const Simulator& simulator, const View& view,
                            std::span<const SurfacePoint> points);
std::vector<std::vector<int>> measuredBy(const Simulator& simulator, std::span<const View> views,
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
// first to `added` (the pinned views, kept through the selection). The sweeps with the
// ids of their views.
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

// The candidate pool: the views added, then every other valid pose evaluated, each with
// the samples it measures.
MeasuredViews candidatePool(const Placement& at, MeasuredViews added,
                            const std::vector<View>& candidates);

// The selection over the pool (indices into it): a greedy set cover by marginal coverage
// from the `pinned` first views, then views whose samples all others also measure dropped
// (last chosen first), then the rest ordered by marginal coverage, priority samples first.
std::vector<std::size_t> selectViews(const Placement& at, const MeasuredViews& pool,
                                     std::size_t pinned, const std::vector<PlannedSample>& samples);

// The selected views as the plan's, ids 1..n in selection order, the task of a candidate
// taken from most of the samples it measures; the samples' measured_by set to them.
void applySelection(const MeasuredViews& pool, const std::vector<std::size_t>& selected,
                    Plan& plan);

// Why each sample still unmeasured is not coverable.
void explainUncoverable(const Placement& at, const std::vector<Visibility>& visibility,
                        std::vector<PlannedSample>& samples);

// The exact set cover of what the plan measures over the whole pool.
PlanBound boundOf(const MeasuredViews& pool, const std::vector<PlannedSample>& samples,
                  double time_limit);

}  // namespace scanplan::detail
