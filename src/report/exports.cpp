// Point exports of a plan: its samples with their coverage, and the simulated clouds of
// its views, as PLY that MeshLab and CloudCompare colour by the red, green, blue columns.

#include <scanplan/report.h>

#include <algorithm>
#include <map>

namespace scanplan {
namespace {

// Fills the red, green, blue columns of `element` from one colour per item.
void addColours(PlyElement& element, const std::vector<Rgb>& colours) {
  const char* names[3] = {"red", "green", "blue"};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> values(colours.size());
    for (std::size_t i = 0; i < colours.size(); ++i) values[i] = colours[i][k];
    element.add(names[k], PlyType::UInt8, std::move(values));
  }
}

template <typename Get>
std::vector<double> column(std::size_t n, Get get) {
  std::vector<double> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = static_cast<double>(get(i));
  return values;
}

// Incidence colours: blue at normal incidence through green to red at 90 degrees.
Rgb incidenceColour(double degrees) {
  const double t = std::clamp(degrees / 90.0, 0.0, 1.0);
  const double r = std::clamp(2 * t, 0.0, 1.0), b = std::clamp(2 - 2 * t, 0.0, 1.0);
  const double g = 1 - std::abs(2 * t - 1);
  return {static_cast<std::uint8_t>(255 * r), static_cast<std::uint8_t>(200 * g),
          static_cast<std::uint8_t>(255 * b)};
}

}  // namespace

PlyData samplesPly(const Plan& plan) {
  const std::vector<PlannedSample>& samples = plan.samples;
  const std::size_t n = samples.size();
  PlyElement vertex{"vertex", n, {}};
  const char* axes[3] = {"x", "y", "z"};
  const char* normal_axes[3] = {"nx", "ny", "nz"};
  for (int k = 0; k < 3; ++k)
    vertex.add(axes[k], PlyType::Float32,
               column(n, [&](std::size_t i) { return samples[i].sample.position[k]; }));
  for (int k = 0; k < 3; ++k)
    vertex.add(normal_axes[k], PlyType::Float32,
               column(n, [&](std::size_t i) { return samples[i].sample.normal[k]; }));
  vertex.add("face", PlyType::Int32,
             column(n, [&](std::size_t i) { return samples[i].sample.face; }));
  vertex.add("task", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].sample.task); }));
  vertex.add("role", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].sample.role); }));
  vertex.add("views", PlyType::UInt16,
             column(n, [&](std::size_t i) { return samples[i].measured_by.size(); }));
  auto state = [&](std::size_t i) {
    return !samples[i].measured_by.empty()               ? 0
           : samples[i].uncoverable == Uncoverable::None ? 1
                                                         : 2;
  };
  vertex.add("state", PlyType::UInt8, column(n, state));
  vertex.add("reason", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].uncoverable); }));
  std::vector<Rgb> colours(n);
  for (std::size_t i = 0; i < n; ++i)
    colours[i] = colour(state(i) == 0   ? FaceCoverage::Measured
                        : state(i) == 1 ? FaceCoverage::Partly
                                        : FaceCoverage::NotMeasured);
  addColours(vertex, colours);
  return {{"scanplan samples, mm, world frame of the plan's first placement",
           "task: 0 gdt, 1 trim, 2 surface, 3 global, 4 points; role: 0 priority, 1 normal, "
           "2 fixture",
           "state: 0 measured, 1 not measured, 2 not coverable; reason: 0 none, 1 below the "
           "working plane, 2 occluded by the part, 3 no valid pose, 4 lost"},
          {std::move(vertex)}};
}

std::vector<PointCloud> sceneClouds(const Plan& plan, const Part& part, const Spec& spec,
                                    double spacing, const Progress& progress) {
  // Each orientation's placement, and which one each view belongs to.
  std::vector<Pose> placements{plan.part_to_world};
  std::map<int, std::size_t> placement_of;
  for (std::size_t k = 1; k < plan.orientations.size(); ++k) {
    placements.push_back(plan.orientations[k].rest.part_to_world);
    for (int id : plan.orientations[k].views) placement_of[id] = k;
  }
  std::vector<PointCloud> clouds(plan.views.size());
  std::size_t done = 0;
  for (std::size_t k = 0; k < placements.size(); ++k) {
    SimulationOptions options = simulationOptionsFor(part, spec, placements[k]);
    const Simulator simulator(part, plan.scanner, options);
    const Pose to_scene = plan.part_to_world * placements[k].inverse();
    for (std::size_t i = 0; i < plan.views.size(); ++i) {
      auto it = placement_of.find(plan.views[i].id);
      if ((it == placement_of.end() ? 0 : it->second) != k) continue;
      report(progress, "simulated clouds",
             static_cast<double>(done++) / static_cast<double>(plan.views.size()));
      PointCloud cloud = simulator.cloud(plan.views[i], static_cast<std::uint64_t>(i + 1), spacing);
      for (Vec3& p : cloud.points) p = to_scene * p;
      for (Vec3& v : cloud.normals) v = to_scene.linear() * v;
      clouds[i] = std::move(cloud);
    }
  }
  report(progress, "simulated clouds", 1);
  return clouds;
}

PlyData cloudsPly(const PlanScene& scene, const std::vector<PointCloud>& clouds) {
  PointCloud all;
  std::vector<double> view_ids;
  for (std::size_t v = 0; v < clouds.size() && v < scene.views.size(); ++v) {
    const PointCloud& c = clouds[v];
    all.points.insert(all.points.end(), c.points.begin(), c.points.end());
    all.normals.insert(all.normals.end(), c.normals.begin(), c.normals.end());
    all.faces.insert(all.faces.end(), c.faces.begin(), c.faces.end());
    all.incidence.insert(all.incidence.end(), c.incidence.begin(), c.incidence.end());
    view_ids.insert(view_ids.end(), c.points.size(), scene.views[v].view.id);
  }
  PlyData data = cloudPly(all);
  data.comments = {
      "scanplan simulated clouds of every view, mm, world frame of the plan's "
      "first placement; view: view id; colour by incidence (blue 0, red 90 degrees)"};
  PlyElement& vertex = data.elements.front();
  vertex.add("view", PlyType::Int32, std::move(view_ids));
  std::vector<Rgb> colours(all.points.size());
  for (std::size_t i = 0; i < colours.size(); ++i) colours[i] = incidenceColour(all.incidence[i]);
  addColours(vertex, colours);
  return data;
}

}  // namespace scanplan
