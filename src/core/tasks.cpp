#include <scanplan/core/tasks.h>

namespace scanplan {

std::string_view toString(TaskType type) {
  switch (type) {
    case TaskType::Gdt: return "gdt";
    case TaskType::Trim: return "trim";
    case TaskType::Surface: return "surface";
    case TaskType::Global: return "global";
    case TaskType::Points: return "points";
  }
  return "unknown";
}

std::string_view toString(Role role) {
  switch (role) {
    case Role::Priority: return "priority";
    case Role::Normal: return "normal";
    case Role::Fixture: return "fixture";
  }
  return "unknown";
}

}  // namespace scanplan
