#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <type_traits>

namespace scanplan {

void setRest(Spec& spec, const std::string& rest, const std::string& key) {
  const bool face = !rest.empty() && rest.size() <= 9 && rest[0] != '0' &&
                    std::all_of(rest.begin(), rest.end(),
                                [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  if (rest != "auto" && rest != "all" && rest != "drawn" && !face)
    throw UsageError(key, "expected auto, all, drawn or a face id, not '" + rest + "'");
  spec.rest_auto = rest == "auto";
  spec.rest_all = rest == "all";
  spec.rest_face = face ? std::stoi(rest) : 0;
  spec.rest_pose.reset();
  spec.rest_given = rest;
}

Spec defaultSpec() {
  Spec spec;
  spec.scanner = scannerPreset("generic-structured-light");
  spec.tasks.push_back(Task{});
  return spec;
}

std::vector<int> gdtFaces(const Part& part, bool dimensions) {
  std::set<int> faces;
  for (const Characteristic& c : characteristics(part.gdt))
    if (dimensions || !c.dimension) faces.insert(c.faces.begin(), c.faces.end());
  for (const Datum& d : part.gdt.datums) faces.insert(d.faces.begin(), d.faces.end());
  return {faces.begin(), faces.end()};
}

namespace {

std::vector<int> without(std::vector<int> faces, const std::vector<int>& removed) {
  std::erase_if(faces,
                [&](int id) { return std::binary_search(removed.begin(), removed.end(), id); });
  return faces;
}

std::vector<int> united(std::vector<int> a, const std::vector<int>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
  return a;
}

// The faces task `k` targets. \throw PlanningError when a task that needs faces has none.
TaskTargets taskTargets(const Part& part, const ResolvedSpec& resolved, std::size_t k) {
  const Task& task = resolved.spec.tasks[k];
  const std::vector<int> named = resolveFaces(part, task.faces, resolved.source);
  TaskTargets targets{task.type, {}, task.points_file, task.points};
  targets.faces = without(task.type == TaskType::Gdt ? united(named, resolved.gdt_faces) : named,
                          resolved.targets.fixture);
  const bool needs_faces =
      task.type == TaskType::Gdt || task.type == TaskType::Trim || task.type == TaskType::Surface;
  if (needs_faces && targets.faces.empty())
    throw PlanningError(resolved.source,
                        "task " + std::to_string(k + 1) + " (" + std::string(toString(task.type)) +
                            ") has no target faces" +
                            (named.empty() ? (task.type == TaskType::Gdt
                                                  ? ": list them, or use gdt: from-file on a part "
                                                    "with GD&T"
                                                  : ": list them")
                                           : ": all of them are fixtures"));
  if (!needs_faces) targets.faces.clear();
  return targets;
}

// Settings absurd for the part's size, refused before anything is allocated for them: a
// field of view that would take more than planner.most_views views to cover the part
// once, surface points for the registration's overlaps (registration.point_spacing) past
// kMostSurfacePoints, a view's ICP cloud (registration.cloud_spacing) past kMostCloudPoints.
void checkScale(const Part& part, const Spec& spec, const std::string& source) {
  constexpr double kMostSurfacePoints = 3e7, kMostCloudPoints = 1e6;
  const Scanner& s = spec.scanner;
  const double area = part.area(), field = s.fov_width * s.fov_height;
  const double views = area / field;
  if (views > spec.planner.most_views) {
    const double k = std::sqrt(views / spec.planner.most_views);
    throw InputError(source,
                     fmt::format("scanner: a {:.4g} x {:.4g} mm field of view is too small for "
                                 "{} ({:.0f} mm² of surface): covering it once takes {:.0f} "
                                 "views, more than planner.most_views ({}); a field of at "
                                 "least {:.3g} x {:.3g} mm",
                                 s.fov_width, s.fov_height, part.file, area, views,
                                 spec.planner.most_views, k * s.fov_width, k * s.fov_height));
  }
  const RegistrationOptions& r = spec.registration;
  const double points = r.point_spacing > 0 ? r.point_spacing : s.fov_height / 40;
  if (area / (points * points) > kMostSurfacePoints)
    throw InputError(source,
                     fmt::format("registration.point_spacing: surface points every {:.3g} mm "
                                 "are more than 30 million over {} ({:.0f} mm²); at least "
                                 "{:.3g} mm",
                                 points, part.file, area, std::sqrt(area / kMostSurfacePoints)));
  if (r.cloud_spacing > 0 && field / (r.cloud_spacing * r.cloud_spacing) > kMostCloudPoints)
    throw InputError(source,
                     fmt::format("registration.cloud_spacing: a cloud point every {:.3g} mm is "
                                 "more than a million points per view; at least {:.3g} mm",
                                 r.cloud_spacing, std::sqrt(field / kMostCloudPoints)));
}

}  // namespace

ResolvedSpec resolveSpec(const Part& part, const Spec& spec) {
  ResolvedSpec resolved;
  resolved.spec = spec;
  resolved.source = spec.source.empty() ? part.file : spec.source;
  checkScale(part, spec, resolved.source);
  if (spec.gdt_from_file) {
    resolved.gdt_faces = gdtFaces(part, spec.gdt_dimensions);
    if (resolved.gdt_faces.empty())
      throw InputError(resolved.source,
                       "gdt: from-file, but " + part.file + " carries no GD&T attached to faces");
  }
  Targets& targets = resolved.targets;
  targets.priority = united(resolveFaces(part, spec.priority, resolved.source), resolved.gdt_faces);
  targets.fixture = resolveFaces(part, spec.fixture, resolved.source);
  resolved.specular = resolveFaces(part, spec.specular, resolved.source);
  for (std::size_t k = 0; k < spec.tasks.size(); ++k) {
    TaskTargets task = taskTargets(part, resolved, k);
    // A task given again targets nothing new: it is sampled once.
    const bool again =
        std::any_of(targets.tasks.begin(), targets.tasks.end(), [&](const TaskTargets& t) {
          return t.type == task.type && t.faces == task.faces && t.points_file == task.points_file;
        });
    if (!again) targets.tasks.push_back(std::move(task));
  }
  if (spec.markers_on_fixture && spec.fixtures.empty() && spec.marker_grid > 0)
    throw InputError(resolved.source, "markers.on: fixture, but the spec has no fixtures");
  const bool on_table = spec.marker_grid > 0 ? spec.markers_on_table
                                             : spec.markers_file_on == MarkerCarrier::Table &&
                                                   !spec.markers_file.empty();
  if (on_table && !(spec.cell && spec.cell->table))
    throw InputError(resolved.source, "markers.on: table, but the cell has no rotary table");
  for (const FixtureModel& fixture : spec.fixtures) {
    ImportOptions options;
    options.read_gdt = false;
    Part model = importPart(fixture.file, options);
    resolved.fixture_model_faces += model.faces.size();
    for (const std::string& warning : model.warnings)
      resolved.warnings.push_back(fixture.file + ": " + warning);
    resolved.fixture_meshes.push_back(std::move(model.mesh));
  }
  return resolved;
}

std::vector<std::string> specFiles(const Spec& spec) {
  std::vector<std::string> files = {spec.source, spec.part_file, spec.markers_file};
  for (const FixtureModel& fixture : spec.fixtures) {
    files.push_back(fixture.file);
    files.push_back(fixture.markers_file);
  }
  for (const Task& task : spec.tasks) files.push_back(task.points_file);
  files.erase(std::remove(files.begin(), files.end(), std::string()), files.end());
  return files;
}

double CoverageTargets::of(Role role, TaskType task) const {
  if (role == Role::Priority) return priority;
  const auto it = tasks.find(task);
  return it == tasks.end() ? others : it->second;
}

bool CoverageTargets::full() const {
  return priority >= 1 && others >= 1 &&
         std::all_of(tasks.begin(), tasks.end(), [](const auto& t) { return t.second >= 1; });
}

RegistrationOptions registrationOptions(const Spec& spec) {
  RegistrationOptions registration = spec.registration;
  registration.seed = spec.planner.seed;
  return registration;
}

void registerByPlacedMarkers(RegistrationOptions& options) {
  if (options.method == RegistrationMode::Geometry) options.method = RegistrationMode::Markers;
}

Pose fixtureToWorld(const FixtureModel& fixture, const Pose& part_to_world) {
  return fixture.in_world ? fixture.placement : Pose(part_to_world * fixture.placement);
}

std::vector<int> resolveFaces(const Part& part, const std::vector<FaceSelector>& selectors,
                              const std::string& source) {
  std::vector<int> ids;
  for (const FaceSelector& selector : selectors) {
    const std::size_t before = ids.size();
    if (selector.id > 0) {
      if (selector.id > static_cast<int>(part.faces.size()))
        throw InputError(source, "unknown face id " + std::to_string(selector.id) + " (" +
                                     part.file + " has " + std::to_string(part.faces.size()) +
                                     " faces)");
      ids.push_back(selector.id);
      continue;
    }
    for (const Face& face : part.faces) {
      bool match = false;
      if (!selector.name.empty())
        match = face.name == selector.name ||
                (face.solid >= 0 && part.solids[face.solid].name == selector.name);
      if (selector.color && face.color) {
        const Color& a = *selector.color;
        const Color& b = *face.color;
        match = std::abs(a.r - b.r) <= 1.f / 255 && std::abs(a.g - b.g) <= 1.f / 255 &&
                std::abs(a.b - b.b) <= 1.f / 255;
      }
      if (match) ids.push_back(face.id);
    }
    if (ids.size() == before)
      throw InputError(
          source, selector.name.empty()
                      ? "no face of " + part.file + " has the colour given"
                      : "no face or solid of " + part.file + " is named '" + selector.name + "'");
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace scanplan
