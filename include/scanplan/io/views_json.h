#pragma once
// Reading views from JSON in the plan format (docs/design.md §7).

#include <scanplan/core/view.h>

#include <string>
#include <vector>

namespace scanplan {

struct ViewsFile {
  std::vector<View> views;
  Pose part_to_world = Pose::Identity();  // from the plan's part section, if any
  bool plan = false;                      // the file is a plan.json (readPlan reads the rest)
};

// Reads `path`: a whole plan.json, an object with a `views` array, or a bare array of
// views. Each view needs `camera_to_world` (4 rows of 4, row-major, rigid); `id` defaults
// to its 1-based position; `target` is optional (then the camera position).
// \throw InputError naming the file and the view (by index and id) that is wrong.
ViewsFile readViews(const std::string& path);

}  // namespace scanplan
