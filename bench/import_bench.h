#pragma once
// The import benchmark's measure, shared by the benchmarks of generated parts.

#include <benchmark/benchmark.h>

#include <string>

namespace scanplan::bench {

// importPart of `path`, and for a STEP file OCCT's own read of it (parse and transfer to
// shapes) in the same iterations: faces, triangles, seconds of each, their ratio.
void importFile(benchmark::State& state, const std::string& path);

}  // namespace scanplan::bench
