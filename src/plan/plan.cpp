// The plan's own queries.

#include <scanplan/plan/plan.h>

#include <algorithm>
#include <map>

namespace scanplan {

std::string_view toString(Uncoverable reason) {
  switch (reason) {
    case Uncoverable::None: return "none";
    case Uncoverable::BelowWorkingPlane: return "occluded_by_working_plane";
    case Uncoverable::OccludedByPart: return "occluded_by_part";
    case Uncoverable::NoValidPose: return "no_valid_pose";
    case Uncoverable::Lost: return "lost_in_simulation";
    case Uncoverable::Unreachable: return "unreachable_by_robot";
  }
  return "unknown";
}

void appendOrientation(Plan& merged, Plan& part, int offset) {
  if (merged.registration && part.registration)
    appendRegistration(*merged.registration, std::move(*part.registration), offset);
  if (merged.sequence && part.sequence) {
    for (int id : part.sequence->views) merged.sequence->views.push_back(id + offset);
    merged.sequence->length += part.sequence->length;
    merged.sequence->nearest_neighbour_length += part.sequence->nearest_neighbour_length;
  }
  for (std::size_t i = 0; i < merged.samples.size(); ++i)
    for (int id : part.samples[i].measured_by) merged.samples[i].measured_by.push_back(id + offset);
}

std::vector<Plan::FaceShortfall> Plan::priorityShortfall() const {
  std::map<int, FaceShortfall> faces;
  for (const PlannedSample& s : samples) {
    if (s.sample.role != Role::Priority) continue;
    FaceShortfall& face = faces[s.sample.face];
    face.face = s.sample.face;
    ++face.samples;
    face.measured += !s.measured_by.empty();
  }
  std::vector<FaceShortfall> short_faces;
  for (const auto& [id, face] : faces)
    if (face.measured < face.samples) short_faces.push_back(face);
  return short_faces;
}

std::vector<SurfacePoint> Plan::samplePoints() const {
  std::vector<SurfacePoint> points;
  for (const PlannedSample& s : samples)
    points.push_back({s.sample.position, s.sample.normal, s.sample.face});
  return points;
}

std::size_t Plan::measuredCount() const {
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(),
                    [](const PlannedSample& s) { return !s.measured_by.empty(); }));
}

Plan::ResultsRow Plan::resultsRow() const {
  ResultsRow row;
  row.model_faces = part_faces;
  row.fixture_faces = fixture_faces;
  row.control_points = std::any_of(samples.begin(), samples.end(), [](const PlannedSample& s) {
    return s.sample.task == TaskType::Points;
  });
  for (const PlannedSample& s : samples)
    if (!row.control_points || s.sample.task == TaskType::Points) {
      ++row.points;
      row.acquired += !s.measured_by.empty();
    }
  row.views = views.size();
  if (registration) row.alignable = registration->registered();
  return row;
}

std::size_t Plan::notCoverableCount() const {
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(),
                    [](const PlannedSample& s) { return s.uncoverable != Uncoverable::None; }));
}

std::size_t Plan::registeredMeasuredCount() const {
  if (!registration) return measuredCount();
  std::vector<char> registered;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const int id = views[v].id;
    if (id >= static_cast<int>(registered.size())) registered.resize(id + 1, 0);
    registered[id] =
        v < registration->views.size() && registration->views[v].method != RegistrationMethod::None;
  }
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(), [&](const PlannedSample& s) {
        return std::any_of(s.measured_by.begin(), s.measured_by.end(), [&](int id) {
          return id < static_cast<int>(registered.size()) && registered[id];
        });
      }));
}

std::vector<std::size_t> viewOrientations(const Plan& plan) {
  std::map<int, std::size_t> of_id;
  for (std::size_t k = 0; k < plan.orientations.size(); ++k)
    for (int id : plan.orientations[k].views) of_id[id] = k;
  std::vector<std::size_t> result(plan.views.size(), 0);
  for (std::size_t i = 0; i < plan.views.size(); ++i)
    if (auto it = of_id.find(plan.views[i].id); it != of_id.end()) result[i] = it->second;
  return result;
}

std::vector<SetupRegistration> setupRegistration(const Plan& plan) {
  std::vector<SetupRegistration> setups(std::max<std::size_t>(1, plan.orientations.size()));
  const std::vector<std::size_t> setup = viewOrientations(plan);
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    ++setups[setup[v]].views;
    setups[setup[v]].registered += plan.registration && v < plan.registration->views.size() &&
                                   plan.registration->views[v].method != RegistrationMethod::None;
  }
  return setups;
}

Pose orientationPlacement(const Plan& plan, std::size_t k) {
  return k < plan.orientations.size() ? plan.orientations[k].rest.part_to_world
                                      : plan.part_to_world;
}

}  // namespace scanplan
