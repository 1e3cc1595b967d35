#pragma once
// Progress reporting for long stages. The library calls a Progress; the CLI decides
// whether and how to show it (a terminal line, nothing under --quiet).

#include <functional>
#include <string_view>

namespace scanplan {

// Called with the stage name and the fraction done in [0, 1]; 1 means the stage ended.
// May be called from worker threads; implementations must be thread-safe.
using Progress = std::function<void(std::string_view stage, double fraction)>;

inline void report(const Progress& progress, std::string_view stage, double fraction) {
  if (progress) progress(stage, fraction);
}

}  // namespace scanplan
