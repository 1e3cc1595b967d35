// The spec's tasks to samples.

#include <scanplan/core/errors.h>
#include <scanplan/sampling/sampling.h>

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
        more = samplePoints(part, task.points, task.points_file, options);
        break;
    }
    samples.insert(samples.end(), more.begin(), more.end());
  }
  return samples;
}

std::vector<SurfacePoint> surfacePoints(const std::vector<Sample>& samples) {
  std::vector<SurfacePoint> points;
  for (const Sample& s : samples) points.push_back({s.position, s.normal, s.face});
  return points;
}

std::vector<SurfacePoint> surfacePoints(const std::vector<Sample>& samples,
                                        const std::vector<int>& members) {
  std::vector<SurfacePoint> points;
  for (int i : members) {
    const Sample& s = samples[static_cast<std::size_t>(i)];
    points.push_back({s.position, s.normal, s.face});
  }
  return points;
}

}  // namespace scanplan
