// Import speed on real parts: STEP reading through XDE, orientation checks and
// tessellation, end to end as importPart() does them, against OCCT's own read of the same
// STEP file (parse and transfer to shapes) in the same run.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Import

#include "import_bench.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/raycast.h>

#include <benchmark/benchmark.h>
#include <STEPControl_Reader.hxx>

#include <chrono>
#include <filesystem>

namespace {

std::string shared(const std::string& relative) {
  return std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// OCCT's own read of a STEP file: parse and transfer to shapes, nothing else.
double occtRead(const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  STEPControl_Reader reader;
  reader.ReadFile(path.c_str());
  reader.TransferRoots();
  benchmark::DoNotOptimize(reader.OneShape());
  return secondsSince(start);
}

}  // namespace

namespace scanplan::bench {

void importFile(benchmark::State& state, const std::string& path) {
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const bool step = path.ends_with(".stp") || path.ends_with(".step");
  std::size_t faces = 0, triangles = 0;
  double occt = 0, ours = 0;
  for (auto _ : state) {
    if (step) occt += occtRead(path);
    const auto start = std::chrono::steady_clock::now();
    scanplan::Part part = scanplan::importPart(path);
    ours += secondsSince(start);
    faces = part.faces.size();
    triangles = part.mesh.triangles.size();
    benchmark::DoNotOptimize(part);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["import_s"] = ours / n;
  state.counters["megabytes"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  if (step) {
    state.counters["occt_read_s"] = occt / n;
    state.counters["import_over_occt"] = ours / occt;
  }
}

}  // namespace scanplan::bench

namespace {

using scanplan::bench::importFile;

// 2,046 faces in 17 solids: the scale target is under 3 s on a 2-core machine.
void BM_ImportLargeAssembly(benchmark::State& state) {
  importFile(state, shared("large/occtpr946_bug31670_russian.stp"));
}
BENCHMARK(BM_ImportLargeAssembly)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ImportNistFtc06(benchmark::State& state) {
  importFile(state, shared("nist/nist_ftc_06_asme1_ap242-e1.stp"));
}
BENCHMARK(BM_ImportNistFtc06)->Unit(benchmark::kMillisecond)->Iterations(3);

// Building the Embree scene of an imported part.
void BM_RayCasterBuild(benchmark::State& state) {
  std::string path = shared("nist/nist_ctc_02_asme1_ap242-e2.stp");
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  scanplan::Part part = scanplan::importPart(path);
  for (auto _ : state) {
    scanplan::RayCaster caster(part.mesh);
    benchmark::DoNotOptimize(caster);
  }
  state.counters["triangles"] = static_cast<double>(part.mesh.triangles.size());
}
BENCHMARK(BM_RayCasterBuild)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
