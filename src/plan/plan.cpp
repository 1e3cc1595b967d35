// The plan's own queries.

#include <scanplan/core/disjoint_sets.h>
#include <scanplan/plan/plan.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <optional>
#include <set>

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
  for (std::size_t k = 0; k < plan.orientations.size(); ++k)
    setups[k].frame = plan.orientations[k].frame;
  const std::vector<std::size_t> setup = viewOrientations(plan);
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    ++setups[setup[v]].views;
    setups[setup[v]].registered += plan.registration && v < plan.registration->views.size() &&
                                   plan.registration->views[v].method != RegistrationMethod::None;
  }
  return setups;
}

std::size_t registeredInOneFrame(const std::vector<SetupRegistration>& setups) {
  std::map<std::size_t, std::size_t> by_frame;
  for (const SetupRegistration& setup : setups) by_frame[setup.frame] += setup.registered;
  std::size_t most = 0;
  for (const auto& [frame, registered] : by_frame) most = std::max(most, registered);
  return most;
}

namespace {

// The markers on the part that the views of a plan see, each by one id over every setup
// (found by its position in the part's frame): per setup, per view registered within it,
// the ids of those it sees, ascending; and each id's position in the part's frame.
struct PartMarkersSeen {
  std::vector<Vec3> positions;
  std::vector<std::vector<std::vector<int>>> by_setup;
};

PartMarkersSeen partMarkersSeen(const Plan& plan) {
  PartMarkersSeen result;
  result.by_setup.resize(plan.orientations.size());
  auto identify = [&](const Vec3& p) {
    for (std::size_t i = 0; i < result.positions.size(); ++i)
      if ((result.positions[i] - p).norm() < 1e-3) return static_cast<int>(i);
    result.positions.push_back(p);
    return static_cast<int>(result.positions.size()) - 1;
  };
  std::vector<std::vector<int>> ids(plan.orientations.size());
  for (std::size_t k = 0; k < plan.orientations.size(); ++k) {
    const PlannedOrientation& o = plan.orientations[k];
    const Pose to_part = o.rest.part_to_world.inverse();
    for (const Marker& m : o.markers)
      ids[k].push_back(m.on == MarkerCarrier::Part ? identify(to_part * m.position) : -1);
  }
  const std::vector<std::size_t> setup = viewOrientations(plan);
  for (std::size_t v = 0; v < plan.views.size() && v < plan.registration->views.size(); ++v) {
    const ViewRegistration& r = plan.registration->views[v];
    if (r.method == RegistrationMethod::None) continue;
    const std::vector<int>& of_setup = ids[setup[v]];
    std::vector<int> seen;
    for (int i : r.markers)
      if (i >= 0 && i < static_cast<int>(of_setup.size()) && of_setup[i] >= 0)
        seen.push_back(of_setup[i]);
    std::sort(seen.begin(), seen.end());
    result.by_setup[setup[v]].push_back(std::move(seen));
  }
  return result;
}

}  // namespace

namespace {

// Whether the part's markers `ids` (of `seen`) register: enough, and not on one line.
bool partMarkersRegister(const PartMarkersSeen& seen, const std::vector<int>& ids,
                         const RegistrationOptions& options) {
  std::vector<Vec3> positions;
  for (int id : ids) positions.push_back(seen.positions[id]);
  return markersRegister(positions, options.min_markers, options.marker_spread);
}

// Markers: setups join where a registered view of each shares enough of the part's markers.
void joinBySharedMarkers(const PartMarkersSeen& seen, const RegistrationOptions& options,
                         DisjointSets& frames) {
  const std::size_t n = seen.by_setup.size();
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t l = k + 1; l < n; ++l)
      for (const std::vector<int>& a : seen.by_setup[k])
        for (const std::vector<int>& b : seen.by_setup[l]) {
          std::vector<int> shared;
          std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
          if (partMarkersRegister(seen, shared, options))
            frames.join(static_cast<int>(l), static_cast<int>(k));
        }
}

// Reference points: every setup with a registered view that sees enough of the part's
// markers registers in their frame.
void joinByKnownMarkers(const PartMarkersSeen& seen, const RegistrationOptions& options,
                        DisjointSets& frames) {
  std::optional<int> framed;  // the first setup in the part's frame
  for (std::size_t k = 0; k < seen.by_setup.size(); ++k) {
    const auto& views = seen.by_setup[k];
    if (std::none_of(views.begin(), views.end(), [&](const std::vector<int>& ids) {
          return partMarkersRegister(seen, ids, options);
        }))
      continue;
    if (framed) frames.join(static_cast<int>(k), *framed);
    framed = framed.value_or(static_cast<int>(k));
  }
}

}  // namespace

void joinSetups(Plan& plan, const RegistrationOptions& options) {
  const std::size_t n = plan.orientations.size();
  for (std::size_t k = 0; k < n; ++k) plan.orientations[k].frame = k;
  if (n < 2 || !plan.registration) return;
  const PartMarkersSeen seen = partMarkersSeen(plan);
  DisjointSets frames(n);
  if (plan.registration->method == RegistrationMode::Markers)
    joinBySharedMarkers(seen, options, frames);
  else if (plan.registration->method == RegistrationMode::ReferencePoints)
    joinByKnownMarkers(seen, options, frames);
  // Each setup's frame named by the first setup in it.
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (frames.find(static_cast<int>(j)) == frames.find(static_cast<int>(k))) {
        plan.orientations[k].frame = j;
        break;
      }
}

Plan setupPlan(const Plan& plan, std::size_t k, int id_offset) {
  const PlannedOrientation& o = plan.orientations.at(k);
  Plan sub = plan;
  sub.orientations.clear();
  sub.part_to_world = o.rest.part_to_world;
  sub.markers = o.markers;
  const Pose to_world = o.rest.part_to_world * plan.part_to_world.inverse();
  const std::set<int> ids(o.views.begin(), o.views.end());
  auto mine = [&](int id) { return ids.count(id) > 0; };
  // A view's id as renumbered; 0 for a view of another setup, which no link crosses.
  auto renumber = [&](int& id) { id = mine(id) ? id - id_offset : 0; };
  sub.views.clear();
  sub.cell_poses.clear();
  if (sub.registration) {
    sub.registration->views.clear();
    std::erase_if(sub.registration->pairs,
                  [&](const PairCheck& p) { return !mine(p.a) || !mine(p.b); });
    for (PairCheck& p : sub.registration->pairs) renumber(p.a), renumber(p.b);
    sub.registration->reference = o.reference;
    renumber(sub.registration->reference);
  }
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    if (!mine(plan.views[v].id)) continue;
    sub.views.push_back(plan.views[v]);
    renumber(sub.views.back().id);
    if (v < plan.cell_poses.size()) sub.cell_poses.push_back(plan.cell_poses[v]);
    if (plan.registration && v < plan.registration->views.size()) {
      sub.registration->views.push_back(plan.registration->views[v]);
      renumber(sub.registration->views.back().to);
    }
  }
  for (PlannedSample& s : sub.samples) {
    s.sample.position = to_world * s.sample.position;
    s.sample.normal = to_world.linear() * s.sample.normal;
    std::erase_if(s.measured_by, [&](int id) { return !mine(id); });
    for (int& id : s.measured_by) renumber(id);
  }
  if (sub.sequence) {
    std::erase_if(sub.sequence->views, [&](int id) { return !mine(id); });
    for (int& id : sub.sequence->views) renumber(id);
  }
  return sub;
}

int setupIdOffset(const Plan& plan, std::size_t k) {
  const std::vector<int>& ids = plan.orientations.at(k).views;
  return ids.empty() ? 0 : *std::min_element(ids.begin(), ids.end()) - 1;
}

Pose orientationPlacement(const Plan& plan, std::size_t k) {
  return k < plan.orientations.size() ? plan.orientations[k].rest.part_to_world
                                      : plan.part_to_world;
}

}  // namespace scanplan
