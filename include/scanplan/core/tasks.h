#pragma once
// Inspection tasks and sample roles (docs/design.md, The spec), and what a task targets
// once its spec is resolved against a part.

#include <scanplan/core/geometry.h>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

enum class TaskType { Gdt, Trim, Surface, Global, Points };
std::string_view toString(TaskType type);
// Every task type, in the order of the enum.
inline constexpr std::array<TaskType, 5> kTaskTypes = {
    TaskType::Gdt, TaskType::Trim, TaskType::Surface, TaskType::Global, TaskType::Points};

enum class Role { Priority, Normal, Fixture };
std::string_view toString(Role role);

// A control point of a `points` task, as its CSV gives it.
struct ControlPoint {
  Vec3 position = Vec3::Zero();  // mm, part frame
  std::optional<Vec3> normal;    // unit when given
  int line = 0;                  // line in the file, for messages
};

// One task resolved against a part: the faces it samples (fixtures removed; gdt with
// gdt: from-file also the part's GD&T faces), or the control points it projects.
struct TaskTargets {
  TaskType type = TaskType::Global;
  std::vector<int> faces;            // 1-based face ids, sorted (gdt, trim, surface)
  std::string points_file;           // points: the CSV they were read from, for messages
  std::vector<ControlPoint> points;  // points
};

// What sampling targets: every task's faces, and the faces of each role.
struct Targets {
  std::vector<TaskTargets> tasks;
  std::vector<int> priority;  // sorted face ids whose global samples are priority
  std::vector<int> fixture;   // sorted face ids never sampled
};

}  // namespace scanplan
