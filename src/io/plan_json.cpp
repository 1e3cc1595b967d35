#include "io/json_values.h"

#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/views_json.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

namespace scanplan {
namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

double share(std::size_t part, std::size_t whole) {
  return whole ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

json matrix(const Pose& pose) {
  json rows = json::array();
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r) rows.push_back(json::array({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}));
  return rows;
}

json markersJson(const std::vector<Marker>& markers) {
  json list = json::array();
  for (const Marker& m : markers)
    list.push_back({{"position", vec(m.position)}, {"normal", vec(m.normal)}});
  return list;
}

}  // namespace

json planJson(const Plan& plan) {
  const Scanner& s = plan.scanner;
  json views = json::array(), sequence = json::array(), samples = json::array();
  const Registration* registration = plan.registration ? &*plan.registration : nullptr;
  std::vector<int> unregistrable;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const View& view = plan.views[v];
    json entry = {{"id", view.id},
                  {"camera_to_world", matrix(view.camera_to_world)},
                  {"target", vec(view.target)},
                  {"task", view.task},
                  {"registration", nullptr}};
    if (registration && v < registration->views.size()) {
      const ViewRegistration& r = registration->views[v];
      entry["registration"] = {
          {"method", toString(r.method)}, {"to", r.to}, {"constrained", r.constrained}};
      entry["bridge"] = r.bridge;
      if (r.method == RegistrationMethod::None) unregistrable.push_back(view.id);
    }
    views.push_back(entry);
  }
  if (plan.sequence) {
    sequence = plan.sequence->views;
  } else {
    for (const View& view : plan.views) sequence.push_back(view.id);
  }
  std::map<std::string, std::size_t> reasons;
  for (const PlannedSample& p : plan.samples) {
    json entry = {{"position", vec(p.sample.position)},
                  {"normal", vec(p.sample.normal)},
                  {"face", p.sample.face},
                  {"role", toString(p.sample.role)},
                  {"task", toString(p.sample.task)},
                  {"measured_by", p.measured_by}};
    if (p.uncoverable != Uncoverable::None) {
      entry["not_coverable"] = toString(p.uncoverable);
      if (p.uncoverable == Uncoverable::Lost) entry["loss"] = toString(p.last_loss);
      ++reasons[std::string(toString(p.uncoverable))];
    }
    samples.push_back(entry);
  }
  json times = json::object();
  for (const StageTime& t : plan.times) times[t.stage] = t.seconds;
  json result = {
      {"format", "scanplan.plan"},
      {"version", 1},
      {"units", "mm"},
      {"part",
       {{"file", plan.part_file},
        {"faces", plan.part_faces},
        {"part_to_world", matrix(plan.part_to_world)}}},
      {"scanner",
       {{"name", s.name},
        {"standoff", s.standoff},
        {"depth_of_field", s.depth_of_field},
        {"fov_width", s.fov_width},
        {"fov_height", s.fov_height},
        {"triangulation_angle", s.triangulation_angle},
        {"max_camera_angle", s.max_camera_angle},
        {"max_projector_angle", s.max_projector_angle},
        {"reflection_cone", s.reflection_cone},
        {"point_spacing", s.point_spacing},
        {"noise_sigma", s.noise_sigma},
        {"body_margin", s.body_margin},
        {"body_depth", s.body_depth}}},
      {"views", views},
      {"sequence", sequence},
      {"samples", samples},
      {"summary",
       {{"model_faces", plan.part_faces},
        {"fixture_faces", plan.fixture_faces},
        {"samples", plan.samples.size()},
        {"measured", plan.measuredCount()},
        {"measured_share", share(plan.measuredCount(), plan.samples.size())},
        {"not_coverable", plan.notCoverableCount()},
        {"not_coverable_by_reason", reasons},
        {"views", plan.views.size()},
        {"registrable_views", nullptr},
        {"seconds", plan.seconds},
        {"stage_seconds", times}}},
  };
  if (registration) {
    json& summary = result["summary"];
    summary["registrable_views"] = registration->registered();
    summary["registered_share"] = share(registration->registered(), plan.views.size());
    summary["measured_by_registered_views"] = plan.registeredMeasuredCount();
    summary["bridging_views"] = registration->bridging_views;
    summary["unregistrable_views"] = unregistrable;
    summary["registration_components"] = registration->components;
    if (plan.sequence) {
      summary["path_length"] = plan.sequence->length;
      summary["nearest_neighbour_path_length"] = plan.sequence->nearest_neighbour_length;
    }
    json pairs = json::array();
    for (const PairCheck& p : registration->pairs) {
      json pair = {{"views", {p.a, p.b}},
                   {"shared_markers", p.shared_markers},
                   {"markers", p.markers},
                   {"overlap_area", p.overlap_area},
                   {"overlap_share", {p.overlap_a, p.overlap_b}},
                   {"condition", std::isfinite(p.condition) ? json(p.condition) : json(nullptr)},
                   {"stable", p.stable},
                   {"registrable", p.registrable()}};
      if (p.icp)
        pair["icp"] = {{"error", p.icp->error},       {"max_error", p.icp->max_error},
                       {"rotation", p.icp->rotation}, {"fitness", p.icp->fitness},
                       {"rmse", p.icp->rmse},         {"points", p.icp->points},
                       {"passed", p.icp->passed}};
      pairs.push_back(pair);
    }
    result["registration"] = {{"reference", registration->reference},
                              {"markers", markersJson(plan.markers)},
                              {"pairs", pairs}};
  }
  if (!plan.orientations.empty()) {
    json orientations = json::array();
    std::map<int, int> orientation_of;
    for (std::size_t k = 0; k < plan.orientations.size(); ++k) {
      const PlannedOrientation& o = plan.orientations[k];
      for (int id : o.views) orientation_of[id] = static_cast<int>(k) + 1;
      orientations.push_back({{"id", k + 1},
                              {"part_to_world", matrix(o.rest.part_to_world)},
                              {"down", vec(o.rest.down)},
                              {"margin", o.rest.margin},
                              {"views", o.views},
                              {"reference", o.reference},
                              {"markers", markersJson(o.markers)}});
    }
    for (json& view : result["views"]) view["orientation"] = orientation_of[view["id"].get<int>()];
    result["orientations"] = orientations;
    result["summary"]["orientations"] = plan.orientations.size();
  }
  if (plan.cell) {
    const Cell& cell = *plan.cell;
    auto in_degrees = [](const Joints& q) {
      json values = json::array();
      for (double a : q) values.push_back(degrees(a));
      return values;
    };
    json robot = {{"model", cell.robot.name},
                  {"base", matrix(cell.base)},
                  {"mount", matrix(cell.mount)},
                  {"lower", in_degrees(cell.robot.lower)},
                  {"upper", in_degrees(cell.robot.upper)},
                  {"speeds", in_degrees(cell.robot.speeds)},
                  {"table", nullptr}};
    if (cell.table)
      robot["table"] = {
          {"origin", vec(cell.table->origin)},
          {"axis", vec(cell.table->axis)},
          {"range", {degrees(cell.table->lower), degrees(cell.table->upper)}}};
    result["cell"] = robot;
    for (std::size_t v = 0; v < plan.views.size() && v < plan.cell_poses.size(); ++v) {
      const std::optional<CellPose>& pose = plan.cell_poses[v];
      result["views"][v]["robot"] =
          pose ? json{{"joints", in_degrees(pose->joints)},
                      {"table", degrees(pose->table_angle)},
                      {"flange", matrix(forwardKinematics(cell.robot, pose->joints))}}
               : json(nullptr);
    }
    const JointMotion motion = jointMotion(cell, plan.cell_poses, plan.views, visitingOrder(plan));
    result["summary"]["robot"] = {{"max_joint_step", degrees(motion.max_step)},
                                  {"max_joint_step_joint", motion.max_step_joint},
                                  {"travel_seconds", motion.seconds},
                                  {"table_moves", motion.table_moves},
                                  {"unreached_views", motion.unreached}};
  }
  if (!plan.sweeps.empty()) {
    json sweeps = json::array();
    std::size_t sweep_views = 0;
    for (const Sweep& sweep : plan.sweeps) {
      json entry = {{"task", toString(sweep.task)},
                    {"faces", sweep.faces},
                    {"tiles", sweep.tiles},
                    {"views", sweep.views},
                    {"patch", nullptr}};
      if (sweep.patch)
        entry["patch"] = {
            {"direction", vec(plan.part_to_world.linear() * sweep.patch->frame.linear().col(2))},
            {"max_deviation", sweep.patch->max_deviation},
            {"tolerance", sweep.patch->tolerance},
            {"file", sweep.patch_file.empty() ? json(nullptr) : json(sweep.patch_file)}};
      sweep_views += sweep.views.size();
      sweeps.push_back(entry);
    }
    result["sweeps"] = sweeps;
    result["summary"]["sweep_views"] = sweep_views;
  }
  if (plan.bound) {
    const PlanBound& b = *plan.bound;
    result["summary"]["bound"] = {
        {"candidates", b.candidates},
        {"ilp_views", b.ilp_views},
        {"lower_bound", b.lower_bound},
        {"optimal", b.optimal},
        {"views_over_ilp",
         b.ilp_views ? static_cast<double>(plan.views.size()) / static_cast<double>(b.ilp_views)
                     : 0.0},
        {"seconds", b.seconds}};
  }
  return result;
}

void writePlan(const Plan& plan, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) { out << planJson(plan).dump(1) << '\n'; });
}

namespace {

// The value of `key` in `object` as a T. \throw InputError naming the file and the key.
template <typename T>
T field(const json& object, const std::string& key, const std::string& path,
        const std::string& where) {
  if (!object.is_object() || !object.contains(key))
    throw InputError(path, where + ": no '" + key + "'");
  try {
    return object[key].get<T>();
  } catch (const json::exception&) {
    throw InputError(path, where + ": '" + key + "' has the wrong type");
  }
}

template <typename Enum, std::size_t N>
Enum enumFrom(const std::string& text, const std::array<Enum, N>& values, const std::string& path,
              const std::string& where) {
  for (Enum value : values)
    if (toString(value) == text) return value;
  throw InputError(path, where + ": unknown value '" + text + "'");
}

}  // namespace

Plan readPlan(const std::string& path) {
  ViewsFile views = readViews(path);  // checks the file, the JSON and every view
  std::ifstream in(path);
  const json root = json::parse(in, nullptr, false);
  if (field<std::string>(root, "format", path, "plan") != "scanplan.plan")
    throw InputError(path, "not a scanplan plan (format is not 'scanplan.plan')");
  Plan plan;
  plan.part_to_world = views.part_to_world;
  plan.views = std::move(views.views);
  const json& part = root.contains("part") ? root["part"] : json();
  plan.part_file = field<std::string>(part, "file", path, "part");
  plan.part_faces = field<std::size_t>(part, "faces", path, "part");

  const json& scanner = root.contains("scanner") ? root["scanner"] : json();
  if (!scanner.is_object()) throw InputError(path, "no 'scanner' object");
  Scanner& s = plan.scanner;
  if (scanner.contains("name") && scanner["name"].is_string()) s.name = scanner["name"];
  for (auto [key, value] : {std::pair<const char*, double*>{"standoff", &s.standoff},
                            {"depth_of_field", &s.depth_of_field},
                            {"fov_width", &s.fov_width},
                            {"fov_height", &s.fov_height},
                            {"triangulation_angle", &s.triangulation_angle},
                            {"max_camera_angle", &s.max_camera_angle},
                            {"max_projector_angle", &s.max_projector_angle},
                            {"reflection_cone", &s.reflection_cone},
                            {"point_spacing", &s.point_spacing},
                            {"noise_sigma", &s.noise_sigma},
                            {"body_margin", &s.body_margin},
                            {"body_depth", &s.body_depth}})
    if (scanner.contains(key)) *value = field<double>(scanner, key, path, "scanner");
  validate(s, path);

  const json& entries = root.contains("views") ? root["views"] : json::array();
  std::vector<ViewRegistration> registration(plan.views.size());
  bool registered = false;
  for (std::size_t v = 0; v < plan.views.size() && v < entries.size(); ++v) {
    const json& r = entries[v].value("registration", json());
    if (!r.is_object()) continue;
    const std::string where = "view " + std::to_string(plan.views[v].id) + " registration";
    registration[v].method =
        enumFrom(field<std::string>(r, "method", path, where),
                 std::array{RegistrationMethod::Reference, RegistrationMethod::Markers,
                            RegistrationMethod::Icp, RegistrationMethod::None},
                 path, where);
    registration[v].to = r.value("to", 0);
    registration[v].bridge = entries[v].value("bridge", false);
    registered = true;
  }
  if (registered) {
    plan.registration.emplace();
    plan.registration->views = registration;
  }
  auto readMarkers = [&](const json& list) {
    std::vector<Marker> markers;
    if (list.is_array())
      for (const json& m : list)
        markers.push_back({detail::vectorFrom(m.value("position", json()), path, "marker"),
                           detail::vectorFrom(m.value("normal", json()), path, "marker")});
    return markers;
  };
  if (root.contains("registration") && root["registration"].is_object())
    plan.markers = readMarkers(root["registration"].value("markers", json()));
  if (root.contains("orientations")) {
    const json& list = root["orientations"];
    if (!list.is_array()) throw InputError(path, "'orientations' is not an array");
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string where = "orientation " + std::to_string(k + 1);
      PlannedOrientation o;
      o.rest.part_to_world =
          Pose(detail::matrixFrom(list[k].value("part_to_world", json()), path, where));
      o.rest.down = detail::vectorFrom(list[k].value("down", json()), path, where);
      o.rest.margin = list[k].value("margin", 0.0);
      o.views = field<std::vector<int>>(list[k], "views", path, where);
      o.reference = list[k].value("reference", 0);
      o.markers = readMarkers(list[k].value("markers", json()));
      plan.orientations.push_back(std::move(o));
    }
  }

  const json& samples = root.contains("samples") ? root["samples"] : json();
  if (!samples.is_array()) throw InputError(path, "no 'samples' array");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const json& entry = samples[i];
    const std::string where = "sample " + std::to_string(i + 1);
    PlannedSample p;
    p.sample.position = detail::vectorFrom(entry.value("position", json()), path, where);
    p.sample.normal = detail::vectorFrom(entry.value("normal", json()), path, where);
    if (!(std::abs(p.sample.normal.norm() - 1) < 1e-3))
      throw InputError(path, where + ": the normal is not a unit vector");
    p.sample.face = field<int>(entry, "face", path, where);
    p.sample.role = enumFrom(field<std::string>(entry, "role", path, where),
                             std::array{Role::Priority, Role::Normal, Role::Fixture}, path, where);
    p.sample.task = enumFrom(field<std::string>(entry, "task", path, where),
                             std::array{TaskType::Gdt, TaskType::Trim, TaskType::Surface,
                                        TaskType::Global, TaskType::Points},
                             path, where);
    p.measured_by = field<std::vector<int>>(entry, "measured_by", path, where);
    if (entry.contains("not_coverable"))
      p.uncoverable = enumFrom(
          field<std::string>(entry, "not_coverable", path, where),
          std::array{Uncoverable::BelowWorkingPlane, Uncoverable::OccludedByPart,
                     Uncoverable::NoValidPose, Uncoverable::Lost, Uncoverable::Unreachable},
          path, where);
    plan.samples.push_back(p);
  }
  if (root.contains("sequence")) {
    plan.sequence.emplace();
    plan.sequence->views = field<std::vector<int>>(root, "sequence", path, "plan");
  }
  return plan;
}

}  // namespace scanplan
