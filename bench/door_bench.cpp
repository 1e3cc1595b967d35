// The car-door case at scale (bench/door_panel.h): a generated door-like panel of about
// 6,000 B-spline faces in a marker frame. Its import against OCCT's own STEP read of the
// same file, in the same run, and the plan of its 107 control points after import.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Door

#include "door_panel.h"
#include "import_bench.h"

#include <scanplan/cad/import.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/spec/spec.h>

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

// The door written once per run, in the system's temporary folder.
const scanplan::bench::DoorCase& door() {
  static const scanplan::bench::DoorCase written = [] {
    const auto folder = std::filesystem::temp_directory_path() / "scanplan_bench_door";
    std::filesystem::create_directories(folder);
    scanplan::bench::DoorOptions options;
    // A field of view that reaches the frame from the middle of the door.
    options.scanner =
        "{preset: generic-structured-light, fov_width: 600, fov_height: 450, "
        "standoff: 800, depth_of_field: 300, point_spacing: 0.4}";
    return scanplan::bench::writeDoorCase(folder.string(), options);
  }();
  return written;
}

void BM_ImportDoor(benchmark::State& state) { scanplan::bench::importFile(state, door().part); }
BENCHMARK(BM_ImportDoor)->Unit(benchmark::kMillisecond)->Iterations(3);

// The points plan of the door in its marker frame, after import: with the bench's scanner
// (range 0), with the default one (range 1), whose field of view does not reach the frame
// from the middle of the door; with the default one registered by reference points (the
// frame's markers known in one frame, range 2), the same with the markers it proposes placed
// (range 4), and without registration (range 3).
void BM_PlanDoor(benchmark::State& state) {
  const auto& written = door();
  const scanplan::Part part = scanplan::importPart(written.part);
  scanplan::Spec spec = scanplan::loadSpec(written.spec);
  if (state.range(0) >= 1) spec.scanner = scanplan::defaultSpec().scanner;
  if (state.range(0) == 2 || state.range(0) == 4)
    spec.registration.method = scanplan::RegistrationMode::ReferencePoints;
  scanplan::PlanningOptions options;
  options.registration = state.range(0) != 3;
  scanplan::Plan plan;
  std::size_t placed = 0;
  for (auto _ : state) {
    plan = scanplan::planViews(part, spec, options);
    if (state.range(0) != 4) continue;
    scanplan::PlacedMarkers marked = scanplan::planWithProposedMarkers(part, spec, plan);
    plan = std::move(marked.plan);
    placed = marked.placed.size();
  }
  const scanplan::Plan::ResultsRow row = plan.resultsRow();
  state.counters["model_faces"] = static_cast<double>(row.model_faces);
  state.counters["fixture_faces"] = static_cast<double>(row.fixture_faces);
  state.counters["points"] = static_cast<double>(row.points);
  state.counters["acquired"] = static_cast<double>(row.acquired);
  state.counters["views"] = static_cast<double>(row.views);
  state.counters["alignable"] = static_cast<double>(row.alignable.value_or(0));
  state.counters["plan_s"] = plan.seconds;
  state.counters["markers_placed"] = static_cast<double>(placed);
}
BENCHMARK(BM_PlanDoor)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
