// Writing what a plan shows, on real parts planned once beforehand: the HTML report
// (clouds and visibility maps included), the glTF scene, the picture and the PLY of all
// simulated clouds at 1 mm. Reports seconds and file sizes.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Report

#include <scanplan/cad/import.h>
#include <scanplan/planning.h>
#include <scanplan/report/report.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>

namespace {

using namespace scanplan;

template <typename Write>
double timed(Write write) {
  const auto start = std::chrono::steady_clock::now();
  write();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void reportPart(benchmark::State& state, const std::string& relative, bool gdt) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  if (gdt) {
    spec.gdt_from_file = true;
    spec.tasks = {Task{TaskType::Gdt, {}, {}, {}}, Task{TaskType::Global, {}, {}, {}}};
  }
  const Plan plan = planViews(part, spec);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "scanplan_report_bench";
  std::filesystem::create_directories(dir);
  const std::string html = (dir / "report.html").string(), glb = (dir / "plan.glb").string();
  const std::string png = (dir / "plan.png").string(), ply = (dir / "clouds.ply").string();
  double report = 0, scene = 0, picture = 0, clouds = 0;
  for (auto _ : state) {
    report = timed([&] { writeReport(plan, part, spec, html); });
    scene = timed([&] { writeGlb(planScene(plan, part), glb); });
    picture = timed([&] { writePng(renderScene(planScene(plan, part)), png); });
    clouds = timed([&] { writeCloudsPly(plan, part, spec, 1, Frame::World, ply); });
  }
  auto megabytes = [](const std::string& file) {
    return static_cast<double>(std::filesystem::file_size(file)) / 1e6;
  };
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["triangles"] = static_cast<double>(part.mesh.triangles.size());
  state.counters["report_s"] = report;
  state.counters["report_MB"] = megabytes(html);
  state.counters["glb_s"] = scene;
  state.counters["glb_MB"] = megabytes(glb);
  state.counters["png_s"] = picture;
  state.counters["clouds_ply_s"] = clouds;
  state.counters["clouds_ply_MB"] = megabytes(ply);
  std::filesystem::remove_all(dir);
}

const int registered = [] {
  benchmark::RegisterBenchmark("BM_Report/nist_ctc_01_asme1_ap242-e1.stp",
                               [](benchmark::State& state) {
                                 reportPart(state, "nist/nist_ctc_01_asme1_ap242-e1.stp", true);
                               })
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  benchmark::RegisterBenchmark(
      "BM_Report/asi_repatch-hpdc.stp",
      [](benchmark::State& state) { reportPart(state, "mech/asi_repatch-hpdc.stp", false); })
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  return 0;
}();

}  // namespace
