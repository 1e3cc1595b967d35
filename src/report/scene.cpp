// The scene of a plan: coverage per face, views with their sequence and registration
// state, all in the frame of the plan's first placement.

#include <scanplan/core/errors.h>
#include <scanplan/planning/planner.h>
#include <scanplan/report/scene.h>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <tuple>

namespace scanplan {

std::string_view toString(FaceCoverage coverage) {
  switch (coverage) {
    case FaceCoverage::NotTarget: return "not a target";
    case FaceCoverage::Measured: return "measured";
    case FaceCoverage::Partly: return "partly measured";
    case FaceCoverage::NotMeasured: return "not measured";
  }
  return "?";
}

std::string_view toString(ViewState state) {
  switch (state) {
    case ViewState::Registered: return "registered";
    case ViewState::Bridge: return "bridge";
    case ViewState::Unregistrable: return "unregistrable";
    case ViewState::Unchecked: return "not checked";
  }
  return "?";
}

// The colours follow Okabe and Ito's palette for colour-vision deficiencies ("Color
// Universal Design", 2002): faces in green, orange and vermillion, views in blue, reddish
// purple and black, so that no colour means both a face's coverage and a view's state.
Rgb colour(FaceCoverage coverage) {
  switch (coverage) {
    case FaceCoverage::NotTarget: return {190, 194, 200};
    case FaceCoverage::Measured: return {0, 158, 115};    // bluish green
    case FaceCoverage::Partly: return {230, 159, 0};      // orange
    case FaceCoverage::NotMeasured: return {213, 94, 0};  // vermillion
  }
  return {0, 0, 0};
}

Rgb colour(ViewState state) {
  switch (state) {
    case ViewState::Registered: return {0, 114, 178};    // blue
    case ViewState::Bridge: return {204, 121, 167};      // reddish purple
    case ViewState::Unregistrable: return {20, 20, 20};  // black
    case ViewState::Unchecked: return {110, 110, 110};
  }
  return {0, 0, 0};
}

std::array<Vec3, 5> frustum(const View& view, const Scanner& scanner) {
  const double far = scanner.standoff + scanner.depth_of_field / 2;
  const double half_w = scanner.fov_width / 2 * far / scanner.standoff;
  const double half_h = scanner.fov_height / 2 * far / scanner.standoff;
  std::array<Vec3, 5> corners;
  corners[0] = view.camera();
  corners[1] = view.camera_to_world * Vec3(-half_w, -half_h, far);
  corners[2] = view.camera_to_world * Vec3(half_w, -half_h, far);
  corners[3] = view.camera_to_world * Vec3(half_w, half_h, far);
  corners[4] = view.camera_to_world * Vec3(-half_w, half_h, far);
  return corners;
}

int sampleState(const PlannedSample& sample) {
  return !sample.measured_by.empty() ? 0 : sample.uncoverable == Uncoverable::None ? 1 : 2;
}

namespace {

// The key counted most often (the first of equals).
template <typename Key>
Key commonest(const std::map<Key, std::size_t>& counts) {
  return std::max_element(counts.begin(), counts.end(),
                          [](auto& a, auto& b) { return a.second < b.second; })
      ->first;
}

// Per face of the part: its samples, measured and not coverable, its coverage, whether it
// bears GD&T, and the commonest reason of its not coverable samples.
void sceneFaces(PlanScene& scene, const Plan& plan, const Part& part) {
  std::vector<std::map<Uncoverable, std::size_t>> reasons(part.faces.size());
  std::vector<std::map<Loss, std::size_t>> losses(part.faces.size());
  scene.faces.resize(part.faces.size());
  for (std::size_t f = 0; f < part.faces.size(); ++f) scene.faces[f].id = static_cast<int>(f + 1);
  for (const GeometricTolerance& t : part.gdt.tolerances)
    for (int face : t.faces)
      if (face >= 1 && face <= static_cast<int>(part.faces.size()))
        scene.faces[face - 1].priority = true;
  for (const Datum& d : part.gdt.datums)
    for (int face : d.faces)
      if (face >= 1 && face <= static_cast<int>(part.faces.size()))
        scene.faces[face - 1].priority = true;
  for (const PlannedSample& s : plan.samples) {
    const int face = s.sample.face;
    if (face < 1 || face > static_cast<int>(part.faces.size())) continue;
    FaceStatus& status = scene.faces[face - 1];
    ++status.samples;
    if (!s.measured_by.empty()) ++status.measured;
    if (s.uncoverable != Uncoverable::None) {
      ++status.not_coverable;
      ++reasons[face - 1][s.uncoverable];
    }
    if (s.uncoverable == Uncoverable::Lost) ++losses[face - 1][s.last_loss];
  }
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    FaceStatus& status = scene.faces[f];
    status.coverage = status.samples == 0                 ? FaceCoverage::NotTarget
                      : status.measured == status.samples ? FaceCoverage::Measured
                      : status.measured > 0               ? FaceCoverage::Partly
                                                          : FaceCoverage::NotMeasured;
    if (!reasons[f].empty()) status.reason = commonest(reasons[f]);
    if (!losses[f].empty()) status.loss = commonest(losses[f]);
  }
}

// The plan's views carried into the scene, with their order in the sequence, their
// registration state and the samples each measures; the path through them.
void sceneViews(PlanScene& scene, const Plan& plan) {
  const std::vector<std::size_t> orientation_of = viewOrientations(plan);
  std::map<int, int> order;
  if (plan.sequence)
    for (std::size_t i = 0; i < plan.sequence->views.size(); ++i)
      order.emplace(plan.sequence->views[i], static_cast<int>(i + 1));
  std::map<int, std::size_t> measured_by_view;
  for (const PlannedSample& s : plan.samples)
    for (int id : s.measured_by) ++measured_by_view[id];
  std::map<int, int> index_of;
  for (std::size_t i = 0; i < plan.views.size(); ++i) {
    SceneView v;
    v.view = plan.views[i];
    if (!plan.orientations.empty()) {
      // Carried from the world of the orientation it was planned in into the scene.
      const Pose to_scene =
          plan.part_to_world * orientationPlacement(plan, orientation_of[i]).inverse();
      v.view.camera_to_world = to_scene * v.view.camera_to_world;
      v.view.target = to_scene * v.view.target;
      v.orientation = static_cast<int>(orientation_of[i] + 1);
    }
    if (auto it = order.find(v.view.id); it != order.end()) v.order = it->second;
    if (plan.registration && i < plan.registration->views.size()) {
      const ViewRegistration& r = plan.registration->views[i];
      v.state = r.method == RegistrationMethod::None ? ViewState::Unregistrable
                : r.bridge                           ? ViewState::Bridge
                                                     : ViewState::Registered;
    }
    if (auto it = measured_by_view.find(v.view.id); it != measured_by_view.end())
      v.measured = it->second;
    index_of[v.view.id] = static_cast<int>(i);
    scene.bounds.add(v.view.camera());
    scene.views.push_back(v);
  }
  if (plan.sequence)
    for (int id : plan.sequence->views)
      if (auto it = index_of.find(id); it != index_of.end()) scene.path.push_back(it->second);
}

// Markers: the plan's are in the first placement's world; an orientation's own markers
// are carried into the scene like its views.
void sceneMarkers(PlanScene& scene, const Plan& plan) {
  for (const Marker& m : plan.markers) scene.markers.push_back(m.position);
  for (std::size_t k = 1; k < plan.orientations.size(); ++k) {
    const Pose to_scene = plan.part_to_world * orientationPlacement(plan, k).inverse();
    for (const Marker& m : plan.orientations[k].markers)
      scene.markers.push_back(to_scene * m.position);
  }
  if (plan.proposed_markers && plan.orientations.size() <= 1)
    for (const Marker& m : plan.proposed_markers->markers)
      scene.proposed_markers.push_back(m.position);
  for (const Vec3& m : scene.markers) scene.bounds.add(m);
  for (const Vec3& m : scene.proposed_markers) scene.bounds.add(m);
}

}  // namespace

PlanScene planScene(const Plan& plan, const Part& part) {
  if (plan.part_faces != 0 && plan.part_faces != part.faces.size())
    throw InputError(part.file, fmt::format("the part has {} faces where the plan has {}",
                                            part.faces.size(), plan.part_faces));
  PlanScene scene;
  scene.scanner = plan.scanner;
  scene.mesh = part.mesh;
  for (Vec3& v : scene.mesh.vertices) {
    v = plan.part_to_world * v;
    scene.bounds.add(v);
  }
  sceneFaces(scene, plan, part);
  sceneViews(scene, plan);
  sceneMarkers(scene, plan);
  return scene;
}

std::vector<Vec3> priorityOutlines(const PlanScene& scene) {
  const TriangleMesh& mesh = scene.mesh;
  const std::vector<int> weld = weldVertices(mesh.vertices, 1e-6 * scene.bounds.diagonal());
  // Per (face, welded edge): how many of the face's triangles use it, and its corners.
  std::map<std::tuple<int, int, int>, std::pair<int, std::array<int, 2>>> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int face = mesh.triangle_faces[t];
    if (face < 1 || face > static_cast<int>(scene.faces.size()) || !scene.faces[face - 1].priority)
      continue;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      if (weld[a] == weld[b]) continue;
      auto& [uses, ends] = edges[{face, std::min(weld[a], weld[b]), std::max(weld[a], weld[b])}];
      ++uses;
      ends = {a, b};
    }
  }
  std::vector<Vec3> lines;
  for (const auto& [key, edge] : edges)
    if (edge.first == 1) {
      lines.push_back(mesh.vertices[edge.second[0]]);
      lines.push_back(mesh.vertices[edge.second[1]]);
    }
  return lines;
}

PlanScene planScene(const Plan& plan, const Part& part, const ResolvedSpec& spec) {
  PlanScene scene = planScene(plan, part);
  for (int face : spec.targets.fixture)  // the part's faces that hold it: never targets
    if (face >= 1 && face <= static_cast<int>(scene.faces.size()) &&
        scene.faces[face - 1].samples == 0)
      scene.faces[face - 1].coverage = FaceCoverage::NotTarget;
  for (const TriangleMesh& mesh : fixturesInWorld(spec, plan.part_to_world))
    scene.fixtures.append(mesh, 0);
  for (const Vec3& v : scene.fixtures.vertices) scene.bounds.add(v);
  return scene;
}

std::string_view toString(Frame frame) { return frame == Frame::Cad ? "cad" : "world"; }

Pose sceneTo(const Plan& plan, Frame frame) {
  return frame == Frame::Cad ? plan.part_to_world.inverse() : Pose::Identity();
}

void moveScene(PlanScene& scene, const Pose& to) {
  scene.bounds = Box();
  for (TriangleMesh* mesh : {&scene.mesh, &scene.fixtures})
    for (Vec3& v : mesh->vertices) {
      v = to * v;
      scene.bounds.add(v);
    }
  for (SceneView& v : scene.views) {
    v.view.camera_to_world = to * v.view.camera_to_world;
    v.view.target = to * v.view.target;
    scene.bounds.add(v.view.camera());
  }
  for (std::vector<Vec3>* points : {&scene.markers, &scene.proposed_markers})
    for (Vec3& m : *points) {
      m = to * m;
      scene.bounds.add(m);
    }
}

Rgb faceColour(const PlanScene& scene, int face) {
  if (face == 0) return kFixtureColour;
  return face >= 1 && face <= static_cast<int>(scene.faces.size())
             ? colour(scene.faces[face - 1].coverage)
             : colour(FaceCoverage::NotTarget);
}

}  // namespace scanplan
