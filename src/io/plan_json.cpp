#include "io/json_values.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/patch_file.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/views_json.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <type_traits>

namespace scanplan {
namespace {

// The maker of robot preset `model`; none for an arm given by its parameters. Plans of
// earlier versions name the preset but not its maker.
std::string makerOf(const std::string& model) {
  const std::vector<std::string> presets = robotPresets();
  if (std::find(presets.begin(), presets.end(), model) == presets.end()) return "";
  return robotPreset(model).maker;
}

// `path` made absolute and normal, as a string ("" stays "").
std::string absolutePath(const std::string& path) {
  if (path.empty()) return path;
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  return (ec ? std::filesystem::path(path) : absolute).lexically_normal().string();
}

using nlohmann::json;

using detail::vec;

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
  for (const Marker& m : markers) {
    json entry = {{"position", vec(m.position)}, {"normal", vec(m.normal)}, {"on", toString(m.on)}};
    if (m.placed) entry["placed"] = true;
    list.push_back(entry);
  }
  return list;
}

json scannerJson(const Scanner& scanner) {
  json result = {{"name", scanner.name}};
  for (const ScannerParameter& p : scannerParameters()) result[p.name] = scanner.*p.value;
  return result;
}

// Per view: id, matrix, target, task, and how it registers (with a registration).
json viewsJson(const Plan& plan) {
  json views = json::array();
  const Registration* registration = plan.registration ? &*plan.registration : nullptr;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const View& view = plan.views[v];
    json entry = {{"id", view.id},
                  {"camera_to_world", matrix(view.camera_to_world)},
                  {"target", vec(view.target)},
                  {"task", view.task},
                  {"registration", nullptr}};
    if (registration && v < registration->views.size()) {
      const ViewRegistration& r = registration->views[v];
      entry["registration"] = {{"method", toString(r.method)},
                               {"to", r.to},
                               {"constrained", r.constrained},
                               {"markers", r.markers}};
      entry["bridge"] = r.bridge;
    }
    views.push_back(entry);
  }
  return views;
}

json samplesJson(const Plan& plan) {
  json samples = json::array();
  for (const PlannedSample& p : plan.samples) {
    json entry = {{"position", vec(p.sample.position)},
                  {"normal", vec(p.sample.normal)},
                  {"face", p.sample.face},
                  {"role", toString(p.sample.role)},
                  {"task", toString(p.sample.task)},
                  {"measured_by", p.measured_by}};
    if (p.sample.cluster >= 0) entry["cluster"] = p.sample.cluster;
    if (p.uncoverable != Uncoverable::None) {
      entry["not_coverable"] = toString(p.uncoverable);
      if (p.uncoverable == Uncoverable::Lost) entry["loss"] = toString(p.last_loss);
    }
    samples.push_back(entry);
  }
  return samples;
}

json capabilityJson(const Capability& k) {
  auto finite = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  auto optional = [](const std::optional<double>& x) { return x ? json(*x) : json(nullptr); };
  return {{"area", k.area},
          {"covered", k.covered},
          {"points", k.points},
          {"density", k.density},
          {"largest_gap", finite(k.largest_gap)},
          {"uncertainty", k.uncertainty},
          {"budget",
           {{"noise", k.budget.noise},
            {"registration", k.budget.registration},
            {"scanner", k.budget.scanner}}},
          {"ratio", k.ratio},
          {"verdict", toString(k.verdict)},
          {"reason", toString(k.reason)},
          {"limit", toString(k.limit)},
          {"views", k.views},
          {"inspected_uncertainty", optional(k.inspected_uncertainty)},
          {"inspected_bias", optional(k.inspected_bias)},
          {"inspected_precision", optional(k.inspected_precision)},
          {"rest_orientation", k.rest ? json(*k.rest + 1) : json(nullptr)}};
}

// The characteristics with their capability, and per verdict how many.
void addCharacteristics(const Plan& plan, json& result) {
  json list = json::array();
  std::map<std::string, std::size_t> verdicts;
  for (std::size_t i = 0; i < plan.characteristics.size(); ++i) {
    const Characteristic& c = plan.characteristics[i];
    json entry = characteristicJson(c);
    entry["capability"] = nullptr;
    if (i < plan.capabilities.size()) {
      entry["capability"] = capabilityJson(plan.capabilities[i]);
      ++verdicts[std::string(toString(plan.capabilities[i].verdict))];
    }
    list.push_back(entry);
  }
  result["characteristics"] = list;
  result["summary"]["characteristics"] = verdicts;
  // Each sample's characteristics: those on its face.
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    json ids = json::array();
    for (const Characteristic& c : plan.characteristics)
      if (std::binary_search(c.faces.begin(), c.faces.end(), plan.samples[i].sample.face))
        ids.push_back(c.id);
    if (!ids.empty()) result["samples"][i]["characteristics"] = ids;
  }
}

// The samples measured by the first k views, in the plan's numbering (by marginal
// coverage, bridging views last), for k = 1..n; and the coverable samples: what each view
// adds, and what the last ones cost.
json coverageByViewsJson(const Plan& plan) {
  std::map<int, std::size_t> position;
  for (std::size_t v = 0; v < plan.views.size(); ++v) position[plan.views[v].id] = v;
  std::vector<std::size_t> first(plan.views.size(), 0);  // samples whose first view is v
  for (const PlannedSample& s : plan.samples) {
    std::size_t earliest = plan.views.size();
    for (int id : s.measured_by)
      if (const auto it = position.find(id); it != position.end())
        earliest = std::min(earliest, it->second);
    if (earliest < plan.views.size()) ++first[earliest];
  }
  json measured = json::array();
  std::size_t sum = 0;
  for (std::size_t count : first) measured.push_back(sum += count);
  return {{"coverable", plan.samples.size() - plan.notCoverableCount()}, {"measured", measured}};
}

json summaryJson(const Plan& plan) {
  std::map<std::string, std::size_t> reasons;
  for (const PlannedSample& p : plan.samples)
    if (p.uncoverable != Uncoverable::None) ++reasons[std::string(toString(p.uncoverable))];
  json times = json::object();
  for (const StageTime& t : plan.times) times[t.stage] = t.seconds;
  json short_faces = json::array();
  for (const Plan::FaceShortfall& f : plan.priorityShortfall())
    short_faces.push_back({{"face", f.face}, {"samples", f.samples}, {"measured", f.measured}});
  const Plan::ResultsRow row = plan.resultsRow();
  const json results = {
      {"model_faces", row.model_faces},
      {"fixture_faces", row.fixture_faces},
      {"points", row.control_points ? "control points" : "targets"},
      {"count", row.points},
      {"acquired", row.acquired},
      {"acquired_share", share(row.acquired, row.points)},
      {"views", row.views},
      {"alignable_views", row.alignable ? json(*row.alignable) : json(nullptr)},
      {"alignable_share", row.alignable ? json(share(*row.alignable, row.views)) : json(nullptr)}};
  return {{"model_faces", plan.part_faces},
          {"results", results},
          {"priority_faces_short", short_faces},
          {"fixture_faces", plan.fixture_faces},
          {"samples", plan.samples.size()},
          {"measured", plan.measuredCount()},
          {"measured_share", share(plan.measuredCount(), plan.samples.size())},
          {"not_coverable", plan.notCoverableCount()},
          {"not_coverable_by_reason", reasons},
          {"views", plan.views.size()},
          {"registrable_views", nullptr},
          {"seconds", plan.seconds},
          {"stage_seconds", times},
          {"coverage_by_views", coverageByViewsJson(plan)}};
}

// Each face's area and the area of it measured, and the part's in the summary.
void addFaceAreas(const Plan& plan, json& root) {
  json list = json::array();
  double area = 0, measured = 0;
  for (const FaceArea& f : plan.face_areas) {
    list.push_back({{"face", f.face}, {"area", f.area}, {"measured", f.measured}});
    area += f.area;
    measured += f.measured;
  }
  root["face_areas"] = list;
  root["summary"]["measured_area"] = {
      {"area", area}, {"measured", measured}, {"share", area > 0 ? measured / area : 0.0}};
}

// How many characteristics the first views make capable, when the plan says.
void addCapableByViews(const Plan& plan, json& root) {
  if (plan.capable_by_views.empty()) return;
  std::vector<std::size_t> views, capable;
  for (const CapableCount& c : plan.capable_by_views) {
    views.push_back(c.views);
    capable.push_back(c.capable);
  }
  root["summary"]["capable_by_views"] = {{"views", views}, {"capable", capable}};
}

json cycleJson(const CycleTime& c) {
  json result = {{"model", c.model},   {"seconds", c.total()},
                 {"views", c.views},   {"acquisition", c.acquisition},
                 {"motion", c.motion}, {"table", c.table},
                 {"other", c.other}};
  if (c.turns > 0) {
    result["turns"] = c.turns;
    result["turning"] = c.turning;
  }
  if (!c.by_views.empty()) result["by_views"] = c.by_views;
  return result;
}

json pairJson(const PairCheck& p) {
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
  return pair;
}

// The registration's summary rows and its section: reference, markers, checked pairs.
void addRegistration(const Plan& plan, json& result) {
  const Registration& registration = *plan.registration;
  std::vector<int> unregistrable;
  for (std::size_t v = 0; v < plan.views.size() && v < registration.views.size(); ++v)
    if (registration.views[v].method == RegistrationMethod::None)
      unregistrable.push_back(plan.views[v].id);
  json& summary = result["summary"];
  summary["registrable_views"] = registration.registered();
  summary["registered_share"] = share(registration.registered(), plan.views.size());
  summary["measured_by_registered_views"] = plan.registeredMeasuredCount();
  summary["bridging_views"] = registration.bridging_views;
  summary["unregistrable_views"] = unregistrable;
  summary["registration_components"] = registration.components;
  json setups = json::array();
  const std::vector<SetupRegistration> by_setup = setupRegistration(plan);
  for (const SetupRegistration& setup : by_setup)
    setups.push_back(
        {{"views", setup.views}, {"registered", setup.registered}, {"frame", setup.frame + 1}});
  const bool joined = std::all_of(by_setup.begin(), by_setup.end(),
                                  [&](const SetupRegistration& s) { return s.frame == 0; });
  summary["setups"] = {{"joined", joined},
                       {"registered_in_one_frame", registeredInOneFrame(by_setup)},
                       {"by_setup", setups}};
  json by = json::object();
  for (RegistrationMethod m : kRegistrationMethods)
    by[std::string(toString(m))] =
        std::count_if(registration.views.begin(), registration.views.end(),
                      [&](auto& v) { return v.method == m; });
  summary["registered_by"] = by;
  json pairs = json::array();
  for (const PairCheck& p : registration.pairs) pairs.push_back(pairJson(p));
  result["registration"] = {{"method", toString(registration.method)},
                            {"required", registration.required},
                            {"aligned_as_taken", registration.aligned_as_taken},
                            {"reference", registration.reference},
                            {"markers", markersJson(plan.markers)},
                            {"pairs", pairs},
                            {"verified", registration.verified}};
  if (registration.method == RegistrationMode::Robot)
    result["registration"]["robot_accuracy"] = registration.robot_accuracy;
  if (plan.proposed_markers)
    result["registration"]["proposed_markers"] = {
        {"markers", markersJson(plan.proposed_markers->markers)},
        {"views", plan.proposed_markers->views},
        {"lower_bound", plan.proposed_markers->lower_bound},
        {"unserved", plan.proposed_markers->unserved}};
}

// The rest orientations of a plan over several, and each view's orientation.
void addOrientations(const Plan& plan, json& result) {
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
                            {"frame", o.frame + 1},
                            {"markers", markersJson(o.markers)}});
  }
  for (json& view : result["views"]) view["orientation"] = orientation_of[view["id"].get<int>()];
  result["orientations"] = orientations;
  result["summary"]["orientations"] = plan.orientations.size();
}

json inDegrees(const Joints& q) {
  json values = json::array();
  for (double a : q) values.push_back(degrees(a));
  return values;
}

// The robot's kinematic lengths, mm, by the names of its family.
json robotLengths(const RobotModel& r) {
  if (r.offset_wrist) {
    const OffsetWrist& w = *r.offset_wrist;
    return {{"d1", w.d1}, {"a2", w.a2}, {"a3", w.a3}, {"d4", w.d4}, {"d5", w.d5}, {"d6", w.d6}};
  }
  return {{"a1", r.a1}, {"a2", r.a2}, {"b", r.b},  {"c1", r.c1},
          {"c2", r.c2}, {"c3", r.c3}, {"c4", r.c4}};
}

json signalsJson(const CellSignals& s) {
  json result = {{"view", s.view},
                 {"trigger", s.trigger},
                 {"acknowledge", s.acknowledge},
                 {"timeout", s.timeout}};
  if (s.table)
    result["table"] = {
        {"angle", s.table->angle}, {"move", s.table->move}, {"ready", s.table->ready}};
  return result;
}

// The cell (robot, mount, table), each view's joints and the plan's joint motion.
void addCell(const Plan& plan, json& result) {
  const Cell& cell = *plan.cell;
  const RobotModel& r = cell.robot;
  json robot = {{"model", r.name},
                {"maker", r.maker},
                {"j23_coupling", r.j23_coupling},
                {"family", r.offset_wrist ? "offset-wrist" : "ortho-parallel"},
                {"lengths", robotLengths(r)},
                {"offsets", inDegrees(r.offsets)},
                {"signs", r.signs},
                {"link_radii", r.link_radii},
                {"base", matrix(cell.base)},
                {"mount", matrix(cell.mount)},
                {"lower", inDegrees(r.lower)},
                {"upper", inDegrees(r.upper)},
                {"speeds", inDegrees(r.speeds)},
                {"accelerations", inDegrees(r.accelerations)},
                {"clearance", cell.clearance},
                {"tool",
                 {{"mass", cell.tool.mass},
                  {"centre", cell.tool.centre ? vec(*cell.tool.centre) : json(nullptr)},
                  {"inertia", cell.tool.inertia ? vec(*cell.tool.inertia) : json(nullptr)}}},
                {"signals", signalsJson(cell.signals)},
                {"home", cell.home ? inDegrees(*cell.home) : json(nullptr)},
                {"approach", cell.approach},
                {"joint_margin", degrees(cell.joint_margin)},
                {"link_meshes", cell.link_meshes.size()},
                {"table", nullptr}};
  if (cell.table)
    robot["table"] = {{"origin", vec(cell.table->origin)},
                      {"axis", vec(cell.table->axis)},
                      {"range", {degrees(cell.table->lower), degrees(cell.table->upper)}},
                      {"step", degrees(cell.table->step)},
                      {"speed", degrees(cell.table->speed)},
                      {"acceleration", degrees(cell.table->acceleration)},
                      {"unit", cell.table->unit}};
  result["cell"] = robot;
  for (std::size_t v = 0; v < plan.views.size() && v < plan.cell_poses.size(); ++v) {
    const std::optional<CellPose>& pose = plan.cell_poses[v];
    result["views"][v]["robot"] =
        pose ? json{{"joints", inDegrees(pose->joints)},
                    {"table", degrees(pose->table_angle)},
                    {"flange", matrix(forwardKinematics(cell.robot, pose->joints))}}
             : json(nullptr);
  }
  const JointMotion motion = jointMotion(cell, plan.cell_poses, plan.views, visitingOrder(plan));
  json uncleared = json::array();
  if (plan.cell_motion)
    for (const RobotMove& move : plan.cell_motion->uncleared)
      uncleared.push_back({move.from, move.to});
  result["summary"]["robot"] = {
      {"max_joint_step", degrees(motion.max_step)},
      {"max_joint_step_joint", motion.max_step_joint},
      {"travel_seconds", plan.cell_motion ? json(plan.cell_motion->seconds) : json(nullptr)},
      {"views_travel_seconds", motion.seconds},
      {"uncleared_moves", uncleared},
      {"table_moves", motion.table_moves},
      {"unreached_views", motion.unreached}};
}

void addSweeps(const Plan& plan, json& result) {
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
          {"direction", vec(plan.part_to_world.linear() * sweep.patch->direction)},
          {"max_deviation", sweep.patch->max_deviation},
          {"tolerance", sweep.patch->tolerance},
          {"file", sweep.patch_file.empty() ? json(nullptr) : json(sweep.patch_file)}};
    sweep_views += sweep.views.size();
    sweeps.push_back(entry);
  }
  result["sweeps"] = sweeps;
  result["summary"]["sweep_views"] = sweep_views;
}

json boundJson(const Plan& plan) {
  const PlanBound& b = *plan.bound;
  return {{"views", b.views}, {"greedy_views", b.greedy_views},     {"lower_bound", b.lower_bound},
          {"pool", b.pool},   {"proven_optimal", b.proven_optimal}, {"time_capped", b.time_capped}};
}

}  // namespace

json characteristicJson(const Characteristic& c) {
  return {{"id", c.id},
          {"kind", c.kind},
          {"dimension", c.dimension},
          {"value", c.value},
          {"limits", {c.lower, c.upper}},
          {"datums", c.datums},
          {"faces", c.faces}};
}

json planJson(const Plan& plan) {
  json sequence = json::array();
  if (plan.sequence) {
    sequence = plan.sequence->views;
  } else {
    for (const View& view : plan.views) sequence.push_back(view.id);
  }
  json result = {
      {"format", "scanplan.plan"},
      {"version", kPlanVersion},
      {"units", "mm"},
      {"part",
       {{"file", plan.part_file},
        {"absolute_file",
         plan.part_file.empty() ? json(nullptr) : json(absolutePath(plan.part_file))},
        {"faces", plan.part_faces},
        {"part_to_world", matrix(plan.part_to_world)}}},
      {"scanner", scannerJson(plan.scanner)},
      {"views", viewsJson(plan)},
      {"sequence", sequence},
      {"samples", samplesJson(plan)},
      {"summary", summaryJson(plan)},
  };
  if (plan.registration) addRegistration(plan, result);
  if (plan.sequence) {
    result["summary"]["path_length"] = plan.sequence->length;
    result["summary"]["nearest_neighbour_path_length"] = plan.sequence->nearest_neighbour_length;
  }
  if (!plan.orientations.empty()) addOrientations(plan, result);
  if (plan.cell) addCell(plan, result);
  if (plan.spec) {
    result["spec"] = {{"file", plan.spec->file}, {"text", plan.spec->text}};
    if (!plan.spec->rest.empty()) result["spec"]["rest"] = plan.spec->rest;
  }
  if (!plan.sweeps.empty()) addSweeps(plan, result);
  if (plan.bound) result["summary"]["bound"] = boundJson(plan);
  if (plan.cycle) result["summary"]["cycle"] = cycleJson(*plan.cycle);
  if (!plan.characteristics.empty()) addCharacteristics(plan, result);
  if (!plan.face_areas.empty()) addFaceAreas(plan, result);
  addCapableByViews(plan, result);
  return result;
}

void writePlan(const Plan& plan, const std::string& path) {
  json root = planJson(plan);
  if (!plan.part_file.empty()) {  // relative to the plan, to move with it
    const std::filesystem::path folder = std::filesystem::path(absolutePath(path)).parent_path();
    const std::filesystem::path relative =
        std::filesystem::path(absolutePath(plan.part_file)).lexically_relative(folder);
    if (!relative.empty()) root["part"]["file"] = relative.generic_string();
  }
  writeFileAtomically(path, [&](std::ostream& out) { out << root.dump(1) << '\n'; });
}

void writePlanFiles(const Plan& plan, const std::string& path, FileSet* outputs) {
  FileSet own;
  FileSet& files = outputs ? *outputs : own;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder.empty() ? "." : folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("patch-") && name.ends_with(".step")) files.drop(entry.path().string());
  }
  for (const Sweep& sweep : plan.sweeps)
    if (sweep.patch && !sweep.patch_file.empty())
      writePatch(sweep.patch->shape, files.stage((folder / sweep.patch_file).string()));
  writePlan(plan, files.stage(path));
  if (!outputs) own.commit();
}

namespace {

// True when `value` may be read as a T without a conversion that loses it: a whole number
// for an integer (a float out of its range would be undefined), or a list of them.
template <typename T>
bool fits(const json& value) {
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    return value.is_number_integer() && (std::is_signed_v<T> || !(value.get<long long>() < 0));
  } else if constexpr (std::is_same_v<T, std::vector<int>>) {
    return value.is_array() &&
           std::all_of(value.begin(), value.end(), [](const json& v) { return fits<int>(v); });
  } else {
    return true;
  }
}

// The value of `key` in `object` as a T. \throw InputError naming the file and the key.
template <typename T>
T field(const json& object, const std::string& key, const std::string& path,
        const std::string& where) {
  if (!object.is_object() || !object.contains(key))
    throw InputError(path, where + ": no '" + key + "'");
  if (!fits<T>(object[key])) throw InputError(path, where + ": '" + key + "' has the wrong type");
  try {
    return object[key].get<T>();
  } catch (const json::exception&) {
    throw InputError(path, where + ": '" + key + "' has the wrong type");
  }
}

// field(), or `otherwise` when `object` has no `key`.
template <typename T>
T fieldOr(const json& object, const std::string& key, T otherwise, const std::string& path,
          const std::string& where) {
  return object.is_object() && object.contains(key) ? field<T>(object, key, path, where)
                                                    : otherwise;
}

template <typename Enum, std::size_t N>
Enum enumFrom(const std::string& text, const std::array<Enum, N>& values, const std::string& path,
              const std::string& where) {
  for (Enum value : values)
    if (toString(value) == text) return value;
  throw InputError(path, where + ": unknown value '" + text + "'");
}

// The object at `key` of `root`, or an empty one.
json objectAt(const json& root, const char* key) {
  return root.contains(key) && root[key].is_object() ? root[key] : json::object();
}

// What a plan file reads into, and where errors point.
struct PlanReader {
  const std::string& path;
  int version;  // of the file

  Scanner scanner(const json& root) const {
    const json& entry = root.contains("scanner") ? root["scanner"] : json();
    if (!entry.is_object()) throw InputError(path, "no 'scanner' object");
    Scanner s;
    if (entry.contains("name") && entry["name"].is_string()) s.name = entry["name"];
    for (const ScannerParameter& p : scannerParameters())
      if (entry.contains(p.name)) s.*p.value = field<double>(entry, p.name, path, "scanner");
    validate(s, path);
    return s;
  }

  // summary.capable_by_views: counts of views rising to at most `views`, each with no more
  // capable characteristics than `characteristics`; none when the plan has none.
  std::vector<CapableCount> capableByViews(const json& root, std::size_t views,
                                           std::size_t characteristics) const {
    const json section = root.value("summary", json()).value("capable_by_views", json());
    if (section.is_null()) return {};
    const std::string where = "summary capable_by_views";
    const auto counts = field<std::vector<std::size_t>>(section, "views", path, where);
    const auto capable = field<std::vector<std::size_t>>(section, "capable", path, where);
    std::vector<CapableCount> result;
    for (std::size_t k = 0; k < counts.size(); ++k) {
      if (capable.size() != counts.size() || counts[k] < 1 || counts[k] > views ||
          (k > 0 && counts[k] <= counts[k - 1]) || capable[k] > characteristics)
        throw InputError(path, where + ": expected rising counts of views up to " +
                                   std::to_string(views) + ", each with at most " +
                                   std::to_string(characteristics) + " capable");
      result.push_back({counts[k], capable[k]});
    }
    return result;
  }

  // face_areas: one entry per face, in face order, each a finite area and no more of it
  // measured than there is; none when the plan has no such list.
  std::vector<FaceArea> faceAreas(const json& root, std::size_t faces) const {
    std::vector<FaceArea> result;
    const json list = root.value("face_areas", json());
    if (list.is_null()) return result;
    if (!list.is_array() || list.size() != faces)
      throw InputError(path, "face_areas: expected one entry per face of the part");
    for (std::size_t f = 0; f < list.size(); ++f) {
      const std::string where = "face_areas entry " + std::to_string(f + 1);
      detail::refuseUnknownKeys(list[f], {"face", "area", "measured"}, path, where);
      FaceArea a{field<int>(list[f], "face", path, where),
                 field<double>(list[f], "area", path, where),
                 field<double>(list[f], "measured", path, where)};
      if (a.face != static_cast<int>(f + 1) || !std::isfinite(a.area) || a.area < 0 ||
          !(a.measured >= 0 && a.measured <= a.area * (1 + 1e-9)))
        throw InputError(path, where + ": expected face " + std::to_string(f + 1) +
                                   " with a finite area and at most that measured");
      result.push_back(a);
    }
    return result;
  }

  std::vector<Marker> markers(const json& list) const {
    std::vector<Marker> result;
    if (list.is_array())
      for (const json& m : list) {
        Marker marker{detail::vectorFrom(m.value("position", json()), path, "marker"),
                      detail::vectorFrom(m.value("normal", json()), path, "marker"),
                      m.contains("on") ? enumFrom(field<std::string>(m, "on", path, "marker"),
                                                  kMarkerCarriers, path, "marker")
                                       : MarkerCarrier::Plane};
        marker.placed = fieldOr(m, "placed", false, path, "marker");
        result.push_back(marker);
      }
    return result;
  }

  PairCheck pair(const json& entry, std::size_t k) const {
    const std::string where = "registration pair " + std::to_string(k + 1);
    PairCheck p;
    const auto views = field<std::vector<int>>(entry, "views", path, where);
    const auto shares = field<std::vector<double>>(entry, "overlap_share", path, where);
    if (views.size() != 2 || shares.size() != 2)
      throw InputError(path, where + ": 'views' and 'overlap_share' hold two values");
    p.a = views[0];
    p.b = views[1];
    p.shared_markers = field<std::size_t>(entry, "shared_markers", path, where);
    p.markers = field<bool>(entry, "markers", path, where);
    p.overlap_area = field<double>(entry, "overlap_area", path, where);
    p.overlap_a = shares[0];
    p.overlap_b = shares[1];
    if (entry.contains("condition") && !entry["condition"].is_null())
      p.condition = field<double>(entry, "condition", path, where);
    p.stable = field<bool>(entry, "stable", path, where);
    if (entry.contains("icp")) {
      const json& icp = entry["icp"];
      IcpCheck& c = p.icp.emplace();
      c.error = field<double>(icp, "error", path, where + " icp");
      c.max_error = field<double>(icp, "max_error", path, where + " icp");
      c.rotation = field<double>(icp, "rotation", path, where + " icp");
      c.fitness = field<double>(icp, "fitness", path, where + " icp");
      c.rmse = field<double>(icp, "rmse", path, where + " icp");
      c.points = field<std::size_t>(icp, "points", path, where + " icp");
      c.passed = field<bool>(icp, "passed", path, where + " icp");
    }
    return p;
  }

  // Each view's registration, the checked pairs and the counts; none when the views carry
  // no registration.
  std::optional<Registration> registration(const json& root, const std::vector<View>& views) const {
    const json& entries = root.contains("views") ? root["views"] : json::array();
    Registration result;
    result.views.resize(views.size());
    bool registered = false;
    for (std::size_t v = 0; v < views.size() && v < entries.size(); ++v) {
      const json& r = entries[v].value("registration", json());
      if (!r.is_object()) continue;
      const std::string where = "view " + std::to_string(views[v].id) + " registration";
      ViewRegistration& view = result.views[v];
      const auto method = field<std::string>(r, "method", path, where);
      view.method = method == toString(RegistrationMethod::None)
                        ? RegistrationMethod::None
                        : enumFrom(method, kRegistrationMethods, path, where);
      view.to = fieldOr(r, "to", 0, path, where);
      view.constrained = r.value("constrained", true);
      view.markers = fieldOr(r, "markers", std::vector<int>{}, path, where);
      view.bridge = entries[v].value("bridge", false);
      registered = true;
    }
    if (!registered) return std::nullopt;
    const json section = objectAt(root, "registration");
    const json pairs = section.value("pairs", json::array());
    if (!pairs.is_array()) throw InputError(path, "registration: 'pairs' is not an array");
    for (std::size_t k = 0; k < pairs.size(); ++k) result.pairs.push_back(pair(pairs[k], k));
    result.reference = fieldOr(section, "reference", 0, path, "registration");
    if (section.contains("method"))
      result.method = enumFrom(field<std::string>(section, "method", path, "registration"),
                               kRegistrationModes, path, "registration");
    result.required = section.value("required", true);
    result.aligned_as_taken = fieldOr(section, "aligned_as_taken", true, path, "registration");
    result.robot_accuracy = section.value("robot_accuracy", 0.0);
    result.verified =
        section.value("verified", std::any_of(result.pairs.begin(), result.pairs.end(),
                                              [](auto& p) { return p.icp.has_value(); }));
    const json summary = objectAt(root, "summary");
    result.components =
        fieldOr(summary, "registration_components", std::size_t{0}, path, "summary");
    result.bridging_views = fieldOr(summary, "bridging_views", std::size_t{0}, path, "summary");
    return result;
  }

  Joints joints(const json& entry, const char* key, const std::string& where) const {
    const std::vector<double> values = field<std::vector<double>>(entry, key, path, where);
    if (values.size() != 6) throw InputError(path, where + ": '" + key + "' is not 6 numbers");
    Joints q{};
    for (int i = 0; i < 6; ++i) q[i] = radians(values[i]);
    return q;
  }

  RobotModel robot(const json& entry) const {
    RobotModel r;
    r.name = field<std::string>(entry, "model", path, "cell");
    const json lengths = objectAt(entry, "lengths");
    auto length = [&](const char* key) {
      return field<double>(lengths, key, path, "cell lengths");
    };
    if (fieldOr<std::string>(entry, "family", "ortho-parallel", path, "cell") == "offset-wrist") {
      r.offset_wrist = OffsetWrist{length("d1"), length("a2"), length("a3"),
                                   length("d4"), length("d5"), length("d6")};
    } else {
      r.a1 = length("a1");
      r.a2 = length("a2");
      r.b = length("b");
      r.c1 = length("c1");
      r.c2 = length("c2");
      r.c3 = length("c3");
      r.c4 = length("c4");
    }
    r.offsets = joints(entry, "offsets", "cell");
    r.maker = fieldOr(entry, "maker", makerOf(r.name), path, "cell");
    r.j23_coupling = fieldOr(entry, "j23_coupling", 0.0, path, "cell");
    const std::vector<int> signs = field<std::vector<int>>(entry, "signs", path, "cell");
    for (std::size_t i = 0; i < 6; ++i) r.signs[i] = i < signs.size() && signs[i] == -1 ? -1 : 1;
    r.lower = joints(entry, "lower", "cell");
    r.upper = joints(entry, "upper", "cell");
    r.speeds = joints(entry, "speeds", "cell");
    r.accelerations = entry.contains("accelerations") ? joints(entry, "accelerations", "cell")
                                                      : rampAccelerations(r.speeds);
    const std::vector<double> radii =
        fieldOr(entry, "link_radii", std::vector<double>{}, path, "cell");
    for (std::size_t i = 0; i < 3 && i < radii.size(); ++i) r.link_radii[i] = radii[i];
    return r;
  }

  CellSignals signals(const json& entry) const {
    CellSignals s;
    s.view = fieldOr(entry, "view", s.view, path, "cell signals");
    s.trigger = fieldOr(entry, "trigger", s.trigger, path, "cell signals");
    s.acknowledge = fieldOr(entry, "acknowledge", s.acknowledge, path, "cell signals");
    s.timeout = fieldOr(entry, "timeout", s.timeout, path, "cell signals");
    if (const json table = objectAt(entry, "table"); !table.empty())
      s.table = TableSignals{field<int>(table, "angle", path, "cell signals table"),
                             field<int>(table, "move", path, "cell signals table"),
                             field<int>(table, "ready", path, "cell signals table")};
    return s;
  }

  // The cell the plan was made in. None when it has none, when it names no robot family
  // (written before plans carried their cell whole), or when the cell had link meshes,
  // which stay in their own files.
  std::optional<Cell> cell(const json& root) const {
    const json entry = objectAt(root, "cell");
    if (!entry.contains("family") || fieldOr(entry, "link_meshes", 0, path, "cell") > 0)
      return std::nullopt;
    Cell cell;
    cell.robot = robot(entry);
    cell.base = Pose(detail::matrixFrom(entry.value("base", json()), path, "cell base"));
    cell.mount = Pose(detail::matrixFrom(entry.value("mount", json()), path, "cell mount"));
    cell.clearance = fieldOr(entry, "clearance", cell.clearance, path, "cell");
    const json tool = objectAt(entry, "tool");
    cell.tool.mass = fieldOr(tool, "mass", cell.tool.mass, path, "cell tool");
    if (tool.contains("centre") && !tool["centre"].is_null())
      cell.tool.centre = detail::vectorFrom(tool["centre"], path, "cell tool");
    if (tool.contains("inertia") && !tool["inertia"].is_null())
      cell.tool.inertia = detail::vectorFrom(tool["inertia"], path, "cell tool");
    cell.signals = signals(objectAt(entry, "signals"));
    if (entry.contains("home") && !entry["home"].is_null())
      cell.home = joints(entry, "home", "cell");
    cell.approach = fieldOr(entry, "approach", cell.approach, path, "cell");
    cell.joint_margin =
        radians(fieldOr(entry, "joint_margin", degrees(cell.joint_margin), path, "cell"));
    if (const json table = entry.value("table", json()); table.is_object()) {
      RotaryTable& t = cell.table.emplace();
      t.origin = detail::vectorFrom(table.value("origin", json()), path, "cell table");
      t.axis = detail::vectorFrom(table.value("axis", json()), path, "cell table").normalized();
      const std::vector<double> range =
          field<std::vector<double>>(table, "range", path, "cell table");
      if (range.size() != 2) throw InputError(path, "cell table: 'range' is not [lower, upper]");
      t.lower = radians(range[0]);
      t.upper = radians(range[1]);
      t.step = radians(fieldOr(table, "step", degrees(t.step), path, "cell table"));
      t.speed = radians(fieldOr(table, "speed", degrees(t.speed), path, "cell table"));
      t.acceleration =
          radians(fieldOr(table, "acceleration", degrees(t.acceleration), path, "cell table"));
      t.unit = fieldOr(table, "unit", t.unit, path, "cell table");
    }
    validate(cell, path);
    return cell;
  }

  // Each view's joints and table angle (none where the cell cannot take it).
  std::vector<std::optional<CellPose>> cellPoses(const json& root, std::size_t views) const {
    std::vector<std::optional<CellPose>> poses(views);
    const json& entries = root.contains("views") ? root["views"] : json::array();
    for (std::size_t v = 0; v < views && v < entries.size(); ++v) {
      const json robot = entries[v].value("robot", json());
      if (!robot.is_object()) continue;
      const std::string where = "view " + std::to_string(v + 1) + " robot";
      poses[v] = CellPose{radians(field<double>(robot, "table", path, where)),
                          joints(robot, "joints", where)};
    }
    return poses;
  }

  Characteristic characteristic(const json& entry, std::size_t k) const {
    const std::string where = "characteristic " + std::to_string(k + 1);
    Characteristic c;
    c.id = field<int>(entry, "id", path, where);
    c.kind = field<std::string>(entry, "kind", path, where);
    c.dimension = fieldOr(entry, "dimension", false, path, where);
    c.value = field<double>(entry, "value", path, where);
    const auto limits = field<std::vector<double>>(entry, "limits", path, where);
    if (limits.size() != 2) throw InputError(path, where + ": limits are not [lower, upper]");
    c.lower = limits[0];
    c.upper = limits[1];
    c.datums = fieldOr(entry, "datums", std::vector<std::string>{}, path, where);
    c.faces = field<std::vector<int>>(entry, "faces", path, where);
    return c;
  }

  // A characteristic's capability; none when the file gives none.
  std::optional<Capability> capability(const json& entry, std::size_t k) const {
    const json& section = entry.value("capability", json());
    if (!section.is_object()) return std::nullopt;
    const std::string where = "characteristic " + std::to_string(k + 1) + " capability";
    Capability c;
    c.characteristic = field<int>(entry, "id", path, where);
    c.area = field<double>(section, "area", path, where);
    c.covered = field<double>(section, "covered", path, where);
    c.points = field<double>(section, "points", path, where);
    c.density = field<double>(section, "density", path, where);
    const json gap = section.value("largest_gap", json());
    c.largest_gap = gap.is_number() ? gap.get<double>() : std::numeric_limits<double>::infinity();
    c.uncertainty = field<double>(section, "uncertainty", path, where);
    c.ratio = field<double>(section, "ratio", path, where);
    c.verdict = named<Verdict>(field<std::string>(section, "verdict", path, where), 4, where);
    c.reason = shortfall(field<std::string>(section, "reason", path, where), where);
    if (const json budget = section.value("budget", json()); budget.is_object()) {
      const std::string in = where + " budget";
      c.budget = {field<double>(budget, "noise", path, in),
                  field<double>(budget, "registration", path, in),
                  field<double>(budget, "scanner", path, in)};
    }
    if (const json rest = section.value("rest_orientation", json()); rest.is_number_integer())
      c.rest = rest.get<std::size_t>() - 1;
    if (section.contains("limit"))
      c.limit = named<Limit>(field<std::string>(section, "limit", path, where), kLimits, where);
    c.views = fieldOr(section, "views", std::vector<int>{}, path, where);
    const auto number = [&](const char* name) -> std::optional<double> {
      const json x = section.value(name, json());
      return x.is_number() ? std::optional(x.get<double>()) : std::nullopt;
    };
    c.inspected_uncertainty = number("inspected_uncertainty");
    c.inspected_bias = number("inspected_bias");
    c.inspected_precision = number("inspected_precision");
    return c;
  }

  // A characteristic's shortfall named `name`; versions 1 and 2 named too_uncertain
  // too_noisy.
  Shortfall shortfall(const std::string& name, const std::string& where) const {
    if (version < 3 && name == "too_noisy") return Shortfall::TooUncertain;
    return named<Shortfall>(name, kShortfalls, where);
  }

  // The enum value whose name is `name`, among the first `count`.
  template <class Enum>
  Enum named(const std::string& name, int count, const std::string& where) const {
    for (int k = 0; k < count; ++k)
      if (toString(static_cast<Enum>(k)) == name) return static_cast<Enum>(k);
    throw InputError(path, where + ": unknown value '" + name + "'");
  }

  // The program's travel and the moves it could not clear (summary.robot), if recorded.
  std::optional<CellMotion> cellMotion(const json& root) const {
    const json robot = objectAt(objectAt(root, "summary"), "robot");
    if (!robot.contains("travel_seconds") || robot["travel_seconds"].is_null()) return std::nullopt;
    CellMotion motion{field<double>(robot, "travel_seconds", path, "summary robot"), {}};
    const auto moves =
        fieldOr(robot, "uncleared_moves", std::vector<std::vector<int>>{}, path, "summary robot");
    for (const std::vector<int>& move : moves) {
      if (move.size() != 2)
        throw InputError(path, "summary robot: an uncleared move is not [from, to]");
      motion.uncleared.push_back({move[0], move[1]});
    }
    return motion;
  }

  // The cycle time (summary.cycle), if recorded.
  std::optional<CycleTime> cycle(const json& root) const {
    const json entry = objectAt(objectAt(root, "summary"), "cycle");
    if (entry.empty()) return std::nullopt;
    const std::string where = "summary cycle";
    CycleTime c;
    c.model = field<std::string>(entry, "model", path, where);
    if (c.model != "cell" && c.model != "generic")
      throw InputError(path, where + ": unknown model '" + c.model + "'");
    c.views = field<std::size_t>(entry, "views", path, where);
    c.turns = fieldOr(entry, "turns", std::size_t{0}, path, where);
    double* parts[] = {&c.acquisition, &c.motion, &c.table, &c.other, &c.turning};
    const char* names[] = {"acquisition", "motion", "table", "other", "turning"};
    for (int k = 0; k < 5; ++k) {
      *parts[k] = k < 4 ? field<double>(entry, names[k], path, where)
                        : fieldOr(entry, names[k], 0.0, path, where);
      if (!(*parts[k] >= 0 && std::isfinite(*parts[k])))
        throw InputError(path, where + ": '" + names[k] + "' is not a number of seconds");
    }
    if (entry.contains("by_views")) {
      c.by_views = field<std::vector<double>>(entry, "by_views", path, where);
      if (c.by_views.size() != root.value("views", json::array()).size())
        throw InputError(path, where + ": 'by_views' needs one time per view");
      for (double s : c.by_views)
        if (!(s >= 0 && std::isfinite(s)))
          throw InputError(path,
                           where + ": 'by_views' holds a time that is not a number of seconds");
    }
    return c;
  }

  PlannedOrientation orientation(const json& entry, std::size_t k) const {
    const std::string where = "orientation " + std::to_string(k + 1);
    PlannedOrientation o;
    o.rest.part_to_world =
        Pose(detail::matrixFrom(entry.value("part_to_world", json()), path, where));
    o.rest.down = detail::vectorFrom(entry.value("down", json()), path, where);
    o.rest.margin = entry.value("margin", 0.0);
    o.views = field<std::vector<int>>(entry, "views", path, where);
    o.reference = fieldOr(entry, "reference", 0, path, where);
    const int frame = fieldOr(entry, "frame", static_cast<int>(k) + 1, path, where);
    if (frame < 1 || frame > static_cast<int>(k) + 1)
      throw InputError(path, where + ": 'frame' must name this orientation or an earlier one");
    o.frame = static_cast<std::size_t>(frame - 1);
    o.markers = markers(entry.value("markers", json()));
    return o;
  }

  PlannedSample sample(const json& entry, std::size_t i) const {
    const std::string where = "sample " + std::to_string(i + 1);
    PlannedSample p;
    p.sample.position = detail::vectorFrom(entry.value("position", json()), path, where);
    p.sample.normal = detail::vectorFrom(entry.value("normal", json()), path, where);
    if (!(std::abs(p.sample.normal.norm() - 1) < 1e-3))
      throw InputError(path, where + ": the normal is not a unit vector");
    p.sample.face = field<int>(entry, "face", path, where);
    p.sample.role = enumFrom(field<std::string>(entry, "role", path, where),
                             std::array{Role::Priority, Role::Normal, Role::Fixture}, path, where);
    p.sample.task =
        enumFrom(field<std::string>(entry, "task", path, where), kTaskTypes, path, where);
    p.measured_by = field<std::vector<int>>(entry, "measured_by", path, where);
    if (entry.contains("cluster")) p.sample.cluster = field<int>(entry, "cluster", path, where);
    if (entry.contains("not_coverable"))
      p.uncoverable = enumFrom(
          field<std::string>(entry, "not_coverable", path, where),
          std::array{Uncoverable::BelowWorkingPlane, Uncoverable::OccludedByPart,
                     Uncoverable::NoValidPose, Uncoverable::Lost, Uncoverable::Unreachable},
          path, where);
    if (entry.contains("loss"))
      p.last_loss = enumFrom(field<std::string>(entry, "loss", path, where),
                             std::array{Loss::Measured, Loss::OutsideVolume, Loss::CameraAngle,
                                        Loss::ProjectorAngle, Loss::Reflection, Loss::UnderMarker,
                                        Loss::CameraOccluded, Loss::ProjectorOccluded},
                             path, where);
    return p;
  }
};

// Every id the plan refers to names one of its views, and every sample's face one of its
// part's. \throw InputError naming the file and the first that does not.
void checkReferences(const Plan& plan, const std::string& path) {
  std::set<int> ids;
  for (const View& view : plan.views) ids.insert(view.id);
  auto require = [&](int id, const std::string& where, bool zero_allowed) {
    if ((id == 0 && zero_allowed) || ids.count(id)) return;
    throw InputError(
        path, where + " refers to view " + std::to_string(id) + ", which the plan does not have");
  };
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    const PlannedSample& s = plan.samples[i];
    const std::string where = "sample " + std::to_string(i + 1);
    if (s.sample.face < 1 || static_cast<std::size_t>(s.sample.face) > plan.part_faces)
      throw InputError(path, where + ": face " + std::to_string(s.sample.face) +
                                 " is not a face of the part (1.." +
                                 std::to_string(plan.part_faces) + ")");
    for (int id : s.measured_by) require(id, where + " measured_by", false);
  }
  if (plan.sequence)
    for (int id : plan.sequence->views) require(id, "the sequence", false);
  if (plan.registration) {
    const Registration& r = plan.registration.value();
    for (std::size_t v = 0; v < r.views.size(); ++v)
      require(r.views[v].to, "view " + std::to_string(plan.views[v].id) + " registration", true);
    require(r.reference, "the registration's reference", true);
    for (const PairCheck& pair : r.pairs) {
      require(pair.a, "a registration pair", false);
      require(pair.b, "a registration pair", false);
    }
  }
  // Each view is taken in one setup, when the plan has several.
  std::map<int, std::size_t> setup_of;  // view id: its orientation's place in the list
  for (std::size_t k = 0; k < plan.orientations.size(); ++k)
    for (int id : plan.orientations[k].views) {
      const std::string where = "orientation " + std::to_string(k + 1);
      require(id, where, false);
      if (const auto [it, added] = setup_of.emplace(id, k); !added)
        throw InputError(path, where + " lists view " + std::to_string(id) +
                                   ", which orientation " + std::to_string(it->second + 1) +
                                   " lists too");
    }
  if (!plan.orientations.empty())
    for (const View& view : plan.views)
      if (!setup_of.count(view.id))
        throw InputError(path, "view " + std::to_string(view.id) + " is in no orientation");
  for (const Characteristic& c : plan.characteristics)
    for (int face : c.faces)
      if (face < 1 || static_cast<std::size_t>(face) > plan.part_faces)
        throw InputError(path, "characteristic " + std::to_string(c.id) + " refers to face " +
                                   std::to_string(face) + ", which the part does not have");
  if (plan.cell_motion)
    for (const RobotMove& move : plan.cell_motion->uncleared) {
      require(move.from, "an uncleared move", true);
      require(move.to, "an uncleared move", true);
    }
}

// The part file of a plan read from `path`: relative to the plan's folder, else the
// absolute path beside it, else as written (relative to the current folder, as older plans
// have it); the first that exists.
std::string partFile(const json& part, const std::string& path) {
  const std::string file = field<std::string>(part, "file", path, "part");
  if (file.empty()) return file;
  const std::filesystem::path near_plan =
      (std::filesystem::path(path).parent_path() / file).lexically_normal();
  std::vector<std::string> candidates = {near_plan.string()};
  if (const json absolute = part.value("absolute_file", json()); absolute.is_string())
    candidates.push_back(absolute.get<std::string>());
  candidates.push_back(file);
  std::error_code ec;
  for (const std::string& candidate : candidates)
    if (std::filesystem::exists(candidate, ec)) return candidate;
  return candidates.front();
}

// The view tasks a plan can hold: a task's type, a bridge for registration, or none.
bool knownViewTask(const std::string& task) {
  for (const TaskType type : kTaskTypes)
    if (task == toString(type)) return true;
  return task.empty() || task == "bridge";
}

// Refuses keys unknown in every entry of the list at `key` of `root`, named `what` N.
void checkListKeys(const json& root, const char* key, const char* what,
                   std::initializer_list<const char*> known, const std::string& path) {
  const json list = root.value(key, json::array());
  if (!list.is_array()) return;
  for (std::size_t k = 0; k < list.size(); ++k)
    detail::refuseUnknownKeys(list[k], known, path,
                              what + std::string(" ") + std::to_string(k + 1));
}

// The sections beyond the views and samples: summary, registration, orientations, cell,
// characteristics and sweeps. (Most of the summary is recomputed, not read, save the path
// lengths, the robot's travel and the registration's counts; its keys are checked all the
// same, so that one misspelt is not taken for one read.)
void checkSectionKeys(const json& root, const std::string& path) {
  // clang-format off
  detail::refuseUnknownKeys(objectAt(root, "summary"),
      {"model_faces", "results", "priority_faces_short", "fixture_faces", "samples", "measured",
       "measured_share", "not_coverable", "not_coverable_by_reason", "views",
       "registrable_views", "seconds", "stage_seconds", "characteristics", "registered_share",
       "measured_by_registered_views", "bridging_views", "unregistrable_views",
       "registration_components", "registered_by", "setups", "path_length",
       "nearest_neighbour_path_length", "orientations", "robot", "sweep_views", "bound",
       "cycle", "coverage_by_views", "measured_area", "capable_by_views"},
      path, "summary");
  // clang-format on
  detail::refuseUnknownKeys(objectAt(objectAt(root, "summary"), "cycle"),
                            {"model", "seconds", "views", "acquisition", "motion", "table", "other",
                             "turns", "turning", "by_views"},
                            path, "summary cycle");
  detail::refuseUnknownKeys(objectAt(root, "registration"),
                            {"method", "required", "aligned_as_taken", "reference", "markers",
                             "pairs", "verified", "robot_accuracy", "proposed_markers"},
                            path, "registration");
  // motion_step: written by earlier versions, no longer read.
  detail::refuseUnknownKeys(
      objectAt(root, "cell"),
      {"model",    "maker",         "j23_coupling", "family",      "lengths", "offsets",
       "signs",    "link_radii",    "base",         "mount",       "lower",   "upper",
       "speeds",   "accelerations", "clearance",    "tool",        "signals", "home",
       "approach", "motion_step",   "joint_margin", "link_meshes", "table"},
      path, "cell");
  checkListKeys(root, "orientations", "orientation",
                {"id", "part_to_world", "down", "margin", "views", "reference", "frame", "markers"},
                path);
  checkListKeys(root, "characteristics", "characteristic",
                {"id", "kind", "dimension", "value", "limits", "datums", "faces", "capability"},
                path);
  checkListKeys(root, "sweeps", "sweep", {"task", "faces", "tiles", "views", "patch"}, path);
}

// Refuses what this version does not understand: another version or unit, and keys it
// does not know in the plan, its part, views, samples and the sections it reads.
void checkPlanKeys(const json& root, const std::string& path) {
  if (const int version = field<int>(root, "version", path, "plan");
      version < 1 || version > kPlanVersion)
    throw InputError(path, "version " + std::to_string(version) +
                               " is not one this scanplan reads (it reads versions 1 to " +
                               std::to_string(kPlanVersion) + ")");
  if (const std::string units = field<std::string>(root, "units", path, "plan"); units != "mm")
    throw InputError(path, "units '" + units + "': plans are in mm");
  detail::refuseUnknownKeys(
      root,
      {"format", "version", "units", "part", "scanner", "views", "sequence", "samples", "summary",
       "registration", "orientations", "cell", "sweeps", "characteristics", "face_areas", "spec"},
      path, "plan");
  detail::refuseUnknownKeys(objectAt(root, "spec"), {"file", "text", "rest"}, path, "spec");
  detail::refuseUnknownKeys(objectAt(root, "part"),
                            {"file", "absolute_file", "faces", "part_to_world"}, path, "part");
  const json views = root.value("views", json::array());
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::string where = "view " + std::to_string(v + 1);
    detail::refuseUnknownKeys(views[v],
                              {"id", "camera_to_world", "target", "task", "registration", "bridge",
                               "robot", "orientation"},
                              path, where);
    const std::string task = views[v].value("task", std::string());
    if (!knownViewTask(task)) throw InputError(path, where + ": unknown task '" + task + "'");
  }
  checkSectionKeys(root, path);
  const json samples = root.value("samples", json::array());
  for (std::size_t i = 0; i < samples.size(); ++i)
    detail::refuseUnknownKeys(samples[i],
                              {"position", "normal", "face", "role", "task", "measured_by",
                               "cluster", "not_coverable", "loss", "characteristics"},
                              path, "sample " + std::to_string(i + 1));
}

// The spec the plan was made with (version 4 on), if it names one.
std::optional<PlanSpec> planSpecOf(const json& root, const std::string& path) {
  if (!root.contains("spec")) return std::nullopt;
  return PlanSpec{field<std::string>(root["spec"], "file", path, "spec"),
                  field<std::string>(root["spec"], "text", path, "spec"),
                  fieldOr(root["spec"], "rest", std::string(), path, "spec")};
}

// readPlan without its net for values of the wrong type.
Plan readPlanFields(const std::string& path) {
  ViewsFile views = readViews(path);  // checks the file, the JSON and every view
  std::ifstream in(path);
  const json root = json::parse(in, nullptr, false);
  if (field<std::string>(root, "format", path, "plan") != "scanplan.plan")
    throw InputError(path, "not a scanplan plan (format is not 'scanplan.plan')");
  checkPlanKeys(root, path);
  const PlanReader reader{path, field<int>(root, "version", path, "plan")};
  Plan plan;
  plan.part_to_world = views.part_to_world;
  plan.views = std::move(views.views);
  const json& part = root.contains("part") ? root["part"] : json();
  plan.part_file = partFile(part, path);
  plan.part_faces = field<std::size_t>(part, "faces", path, "part");
  plan.scanner = reader.scanner(root);
  plan.registration = reader.registration(root, plan.views);
  if (root.contains("registration") && root["registration"].is_object()) {
    const json& registration = root["registration"];
    plan.markers = reader.markers(registration.value("markers", json()));
    if (const json proposed = registration.value("proposed_markers", json()); proposed.is_object())
      plan.proposed_markers = MarkerProposal{
          reader.markers(proposed.value("markers", json())),
          fieldOr(proposed, "views", std::size_t{0}, path, "proposed_markers"),
          fieldOr(proposed, "lower_bound", std::size_t{0}, path, "proposed_markers"),
          fieldOr(proposed, "unserved", std::vector<int>{}, path, "proposed_markers")};
  }
  if (root.contains("orientations")) {
    const json& list = root["orientations"];
    if (!list.is_array()) throw InputError(path, "'orientations' is not an array");
    for (std::size_t k = 0; k < list.size(); ++k)
      plan.orientations.push_back(reader.orientation(list[k], k));
  }
  const json& samples = root.contains("samples") ? root["samples"] : json();
  if (!samples.is_array()) throw InputError(path, "no 'samples' array");
  for (std::size_t i = 0; i < samples.size(); ++i)
    plan.samples.push_back(reader.sample(samples[i], i));
  if (root.contains("sequence")) {
    plan.sequence.emplace();
    plan.sequence->views = field<std::vector<int>>(root, "sequence", path, "plan");
    const json summary = objectAt(root, "summary");
    plan.sequence->length = summary.value("path_length", 0.0);
    plan.sequence->nearest_neighbour_length = summary.value("nearest_neighbour_path_length", 0.0);
  }
  if (const json list = root.value("characteristics", json()); list.is_array())
    for (std::size_t k = 0; k < list.size(); ++k) {
      plan.characteristics.push_back(reader.characteristic(list[k], k));
      if (std::optional<Capability> c = reader.capability(list[k], k))
        plan.capabilities.push_back(*c);
    }
  if (plan.capabilities.size() != plan.characteristics.size()) plan.capabilities.clear();
  plan.face_areas = reader.faceAreas(root, plan.part_faces);
  plan.capable_by_views =
      reader.capableByViews(root, plan.views.size(), plan.characteristics.size());
  plan.cell = reader.cell(root);
  if (plan.cell) {
    plan.cell_poses = reader.cellPoses(root, plan.views.size());
    plan.cell_motion = reader.cellMotion(root);
  }
  plan.cycle = reader.cycle(root);
  plan.spec = planSpecOf(root, path);
  checkReferences(plan, path);
  return plan;
}

}  // namespace

Plan readPlan(const std::string& path) {
  try {
    return readPlanFields(path);
  } catch (const nlohmann::json::exception& e) {  // a value of the wrong type left unnamed
    throw InputError(path, std::string("a value has the wrong type: ") + e.what());
  }
}

}  // namespace scanplan
