// View planning on real parts: the gdt task (faces of the AP242 PMI) on every NIST model
// and the global task on a die-cast part. Reports samples, coverage of the coverable
// priority samples, views, views / ILP optimum over the same candidates, and seconds.
// BM_Register: registration, bridging and sequencing of NIST plans, with and without
// markers.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Plan
//
// Coverable: measured by some pose of a dense candidate set (directions every 10° inside
// the camera's glancing cone at the standoff, 8 rotations about the axis; scanner body
// not checked), see coverableByDenseCandidates().

#include <scanplan/cad/import.h>
#include <scanplan/planning.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>

namespace {

using namespace scanplan;

void planPart(benchmark::State& state, const std::string& relative, bool gdt) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  if (gdt) {
    spec.gdt_from_file = true;
    spec.tasks = {Task{TaskType::Gdt, {}, {}}};
  }
  PlanningOptions options;
  options.bound = true;
  options.registration = false;  // BM_Register measures it
  Plan plan;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    plan = planViews(part, spec, options);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // Coverage of the coverable target samples (priority for gdt, all for global) (the bound's time
  // is part of `seconds` above; the plan alone is reported as plan_seconds).
  SimulationOptions simulation;
  simulation.part_to_world = plan.part_to_world;
  const Simulator simulator(part, plan.scanner, simulation);
  std::vector<SurfacePoint> points;
  for (const PlannedSample& s : plan.samples)
    points.push_back({s.sample.position, s.sample.normal, s.sample.face});
  const std::vector<char> coverable = coverableByDenseCandidates(simulator, points);
  double priority = 0, reachable = 0, measured = 0;
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    if (gdt && plan.samples[i].sample.role != Role::Priority) continue;  // global: every sample
    ++priority;
    if (!coverable[i]) continue;
    ++reachable;
    measured += !plan.samples[i].measured_by.empty();
  }
  double bound_seconds = 0;
  for (const StageTime& t : plan.times)
    if (t.stage == "set cover bound") bound_seconds = t.seconds;
  state.counters["samples"] = static_cast<double>(plan.samples.size());
  state.counters["priority"] = priority;
  state.counters["coverable"] = reachable;
  state.counters["coverage"] = reachable > 0 ? measured / reachable : 0;
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["ilp_views"] = static_cast<double>(plan.bound->ilp_views);
  state.counters["ilp_optimal"] = plan.bound->optimal;
  state.counters["views_over_ilp"] =
      static_cast<double>(plan.views.size()) /
      static_cast<double>(std::max<std::size_t>(plan.bound->ilp_views, 1));
  state.counters["plan_seconds"] = seconds - bound_seconds;
}

// Registration, bridging and sequencing after the gdt and global tasks on a NIST model,
// without markers and with markers every 50 mm on the plate and on the part.
void registerPart(benchmark::State& state, const std::string& name, bool markers) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/nist/" + name;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  spec.gdt_from_file = true;
  spec.tasks = {Task{TaskType::Gdt, {}, {}}, Task{TaskType::Global, {}, {}}};
  if (markers) {
    spec.marker_grid = 50;
    spec.markers_on_part = true;
  }
  Plan plan;
  for (auto _ : state) plan = planViews(part, spec);
  const Registration& r = *plan.registration;
  std::size_t verified = 0, passed = 0, unconstrained = 0;
  for (const PairCheck& pair : r.pairs)
    if (pair.icp) {
      ++verified;
      passed += pair.icp->passed;
    }
  for (const ViewRegistration& view : r.views)
    unconstrained += view.method == RegistrationMethod::None && !view.constrained;
  for (const StageTime& t : plan.times)
    if (t.stage == "registration") state.counters["registration_seconds"] = t.seconds;
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["registered"] = static_cast<double>(r.registered());
  state.counters["bridging"] = static_cast<double>(r.bridging_views);
  state.counters["unconstrained"] = static_cast<double>(unconstrained);
  state.counters["icp_verified"] = static_cast<double>(verified);
  state.counters["icp_passed"] = static_cast<double>(passed);
  state.counters["measured"] = static_cast<double>(plan.measuredCount());
  state.counters["measured_registered"] = static_cast<double>(plan.registeredMeasuredCount());
  state.counters["path_m"] = plan.sequence->length / 1000;
  state.counters["nn_path_m"] = plan.sequence->nearest_neighbour_length / 1000;
}

const int registered = [] {
  for (const char* name : {"nist_ctc_01_asme1_ap242-e1.stp", "nist_ctc_03_asme1_ap242-e2.stp",
                           "nist_ftc_06_asme1_ap242-e1.stp"})
    for (const bool markers : {false, true})
      benchmark::RegisterBenchmark(
          (std::string("BM_Register/") + name + (markers ? "/markers" : "/no_markers")).c_str(),
          [name, markers](benchmark::State& state) { registerPart(state, name, markers); })
          ->Unit(benchmark::kSecond)
          ->Iterations(1);
  for (const char* name : {"nist_ctc_01_asme1_ap242-e1.stp", "nist_ctc_02_asme1_ap242-e2.stp",
                           "nist_ctc_03_asme1_ap242-e2.stp", "nist_ctc_04_asme1_ap242-e1.stp",
                           "nist_ftc_06_asme1_ap242-e1.stp", "nist_ftc_07_asme1_ap242-e2.stp",
                           "nist_ftc_08_asme1_ap242-e1.stp", "nist_ftc_11_asme1_ap242-e1.stp"})
    benchmark::RegisterBenchmark(
        (std::string("BM_PlanGdt/") + name).c_str(),
        [name](benchmark::State& state) { planPart(state, std::string("nist/") + name, true); })
        ->Unit(benchmark::kSecond)
        ->Iterations(1);
  benchmark::RegisterBenchmark(
      "BM_PlanGlobal/asi_repatch-hpdc.stp",
      [](benchmark::State& state) { planPart(state, "mech/asi_repatch-hpdc.stp", false); })
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  return 0;
}();

}  // namespace
