// The spec's tasks to samples.

#include <scanplan/errors.h>
#include <scanplan/sampling.h>

#include <algorithm>

namespace scanplan {

SamplingOptions samplingOptionsFor(const Scanner& scanner) {
  SamplingOptions options;
  options.portion_size = std::min(scanner.fov_width, scanner.fov_height);
  options.decimation_radius = options.portion_size / 10;
  return options;
}

std::vector<Sample> sampleTargets(const Part& part, const Targets& targets,
                                  const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (const TaskTargets& task : targets.tasks) {
    std::vector<Sample> more;
    switch (task.type) {
      case TaskType::Gdt:
      case TaskType::Surface:
        more = sampleSurface(part, task.faces, Role::Priority, task.type, options);
        break;
      case TaskType::Trim:
        more = sampleBorders(part, task.faces, Role::Priority, TaskType::Trim, options);
        break;
      case TaskType::Global:
        more = sampleGlobal(part, targets.fixture, options);
        for (Sample& s : more)
          if (std::binary_search(targets.priority.begin(), targets.priority.end(), s.face))
            s.role = Role::Priority;
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
