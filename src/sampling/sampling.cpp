// The spec's tasks to samples.

#include <scanplan/errors.h>
#include <scanplan/sampling.h>

#include <algorithm>
#include <set>

namespace scanplan {

std::string_view toString(Role role) {
  switch (role) {
    case Role::Priority: return "priority";
    case Role::Normal: return "normal";
    case Role::Fixture: return "fixture";
  }
  return "unknown";
}

SamplingOptions samplingOptionsFor(const Scanner& scanner) {
  SamplingOptions options;
  options.portion_size = std::min(scanner.fov_width, scanner.fov_height);
  options.decimation_radius = options.portion_size / 10;
  return options;
}

std::vector<int> gdtFaces(const Part& part) {
  std::set<int> faces;
  for (const GeometricTolerance& t : part.gdt.tolerances)
    faces.insert(t.faces.begin(), t.faces.end());
  for (const Datum& d : part.gdt.datums) faces.insert(d.faces.begin(), d.faces.end());
  return {faces.begin(), faces.end()};
}

namespace {

std::vector<int> without(std::vector<int> faces, const std::vector<int>& removed) {
  faces.erase(
      std::remove_if(
          faces.begin(), faces.end(),
          [&](int id) { return std::find(removed.begin(), removed.end(), id) != removed.end(); }),
      faces.end());
  return faces;
}

std::vector<int> united(std::vector<int> a, const std::vector<int>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
  return a;
}

}  // namespace

std::vector<Sample> sampleSpec(const Part& part, const Spec& spec, const SamplingOptions& options) {
  const std::string& source = spec.source.empty() ? part.file : spec.source;
  const std::vector<int> from_file = spec.gdt_from_file ? gdtFaces(part) : std::vector<int>{};
  if (spec.gdt_from_file && from_file.empty())
    throw InputError(source,
                     "gdt: from-file, but " + part.file + " carries no GD&T attached to faces");
  const std::vector<int> priority = united(resolveFaces(part, spec.priority, source), from_file);
  const std::vector<int> fixture = resolveFaces(part, spec.fixture, source);

  std::vector<Sample> samples;
  for (std::size_t k = 0; k < spec.tasks.size(); ++k) {
    const Task& task = spec.tasks[k];
    const std::vector<int> named = resolveFaces(part, task.faces, source);
    std::vector<int> faces =
        without(task.type == TaskType::Gdt ? united(named, from_file) : named, fixture);
    const bool needs_faces =
        task.type == TaskType::Gdt || task.type == TaskType::Trim || task.type == TaskType::Surface;
    if (needs_faces && faces.empty())
      throw PlanningError(
          source,
          "task " + std::to_string(k + 1) + " (" + std::string(toString(task.type)) +
              ") has no target faces" +
              (named.empty() ? (task.type == TaskType::Gdt
                                    ? ": list them, or use gdt: from-file on a part with GD&T"
                                    : ": list them")
                             : ": all of them are fixtures"));
    std::vector<Sample> more;
    switch (task.type) {
      case TaskType::Gdt:
        more = sampleSurface(part, faces, Role::Priority, TaskType::Gdt, options);
        break;
      case TaskType::Surface:
        more = sampleSurface(part, faces, Role::Priority, TaskType::Surface, options);
        break;
      case TaskType::Trim:
        more = sampleBorders(part, faces, Role::Priority, TaskType::Trim, options);
        break;
      case TaskType::Global:
        more = sampleGlobal(part, fixture, options);
        for (Sample& s : more)
          if (std::binary_search(priority.begin(), priority.end(), s.face)) s.role = Role::Priority;
        break;
      case TaskType::Points:
        more = samplePoints(part, readPointsCsv(task.points_file), task.points_file, options);
        break;
    }
    samples.insert(samples.end(), more.begin(), more.end());
  }
  return samples;
}

}  // namespace scanplan
