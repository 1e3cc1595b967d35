#pragma once
// Bridging views (docs/registration.md): views added where the registration graph falls
// apart, until it is connected or no bridge exists.

#include <scanplan/core/progress.h>
#include <scanplan/planning/poses.h>
#include <scanplan/registration/registration.h>

#include <vector>

namespace scanplan {

// Registers `views` (registerViews) and, with options.bridging, appends views to them until
// the graph is connected or no bridge exists, at most options.max_bridging_views. Bridging
// poses are valid (planning/poses.h: the scanner body clear, the `cell`'s robot reaching
// them). Ids of appended views follow the largest id.
Registration registerWithBridging(const Simulator& simulator, std::vector<View>& views,
                                  const std::vector<Marker>& markers,
                                  const RegistrationOptions& options, const CellCheck& cell,
                                  const Progress& progress = {});

}  // namespace scanplan
