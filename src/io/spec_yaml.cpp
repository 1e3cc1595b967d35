// The spec's YAML (docs/spec.md): read and checked key by key, with the files it names
// resolved to its folder and its control points read.

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/spec_yaml.h>

#include "scanner/sensor_yaml.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <type_traits>

namespace scanplan {

namespace {

// Reads one spec file; every error names it and the key.
class SpecReader {
 public:
  explicit SpecReader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, what); }
  const std::string& path() const { return path_; }

  // A path in the spec, relative to the spec's folder.
  std::string resolvePath(const std::string& file) const {
    std::filesystem::path p(file);
    if (p.is_absolute()) return file;
    return (std::filesystem::path(path_).parent_path() / p).lexically_normal().string();
  }

  // A value of the spec; a number must be finite (YAML's .nan and .inf are refused).
  template <typename T>
  T scalar(const YAML::Node& node, const std::string& key) const {
    T value{};
    try {
      value = node.as<T>();
    } catch (const YAML::Exception&) {
      fail(key + ": '" + YAML::Dump(node) + "' is not a valid value");
    }
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(value)) fail(key + ": '" + YAML::Dump(node) + "' is not a finite number");
    return value;
  }

  // `value` from `section`.`key` of `node` when it is given.
  template <typename T>
  void read(const YAML::Node& node, const std::string& section, const char* key, T& value) const {
    if (node[key]) value = scalar<T>(node[key], section + "." + key);
  }

  Color color(const YAML::Node& node, const std::string& key) const {
    if (node.IsScalar()) {  // "#rrggbb"
      const std::string text = node.as<std::string>();
      if (text.size() != 7 || text[0] != '#' ||
          text.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
        fail(key + ": colour '" + text + "' is not #rrggbb");
      auto channel = [&](int i) {
        return static_cast<float>(std::stoi(text.substr(1 + 2 * i, 2), nullptr, 16)) / 255.f;
      };
      return Color{channel(0), channel(1), channel(2)};
    }
    if (node.IsSequence() && node.size() == 3) {  // [r, g, b] in [0, 1]
      Color c{scalar<float>(node[0], key), scalar<float>(node[1], key),
              scalar<float>(node[2], key)};
      for (float v : {c.r, c.g, c.b})
        if (v < 0 || v > 1) fail(key + ": colour channels must be within [0, 1]");
      return c;
    }
    fail(key + ": a colour is #rrggbb or [r, g, b]");
  }

  std::vector<FaceSelector> faces(const YAML::Node& node, const std::string& key) const {
    std::vector<FaceSelector> selectors;
    if (!node) return selectors;
    if (!node.IsSequence())
      fail(key + " must be a list of faces (ids, {name: ...} or {color: ...})");
    for (const YAML::Node& item : node) {
      FaceSelector selector;
      if (item.IsScalar()) {
        selector.id = scalar<int>(item, key);
        if (selector.id < 1)
          fail(key + ": face ids start at 1, got " + std::to_string(selector.id));
      } else if (item.IsMap() && item["name"]) {
        selector.name = scalar<std::string>(item["name"], key);
        if (selector.name.empty()) fail(key + ": a face name must not be empty");
      } else if (item.IsMap() && (item["color"] || item["colour"])) {
        selector.color = color(item["color"] ? item["color"] : item["colour"], key);
      } else {
        fail(key + ": '" + YAML::Dump(item) + "' is not a face id, {name: ...} or {color: ...}");
      }
      selectors.push_back(selector);
    }
    return selectors;
  }

  // `count` numbers.
  std::vector<double> numbers(const YAML::Node& node, std::size_t count,
                              const std::string& key) const {
    if (!node.IsSequence() || node.size() != count)
      fail(key + ": expected " + std::to_string(count) + " numbers");
    std::vector<double> values;
    for (const YAML::Node& item : node) values.push_back(scalar<double>(item, key));
    return values;
  }

  Vec3 vector(const YAML::Node& node, const std::string& key) const {
    const std::vector<double> v = numbers(node, 3, key);
    return {v[0], v[1], v[2]};
  }

  // Six joint values in degrees (degree: true) or plain numbers, as radians.
  Joints joints(const YAML::Node& node, const std::string& key, bool degree = true) const {
    const std::vector<double> v = numbers(node, 6, key);
    Joints q{};
    for (int i = 0; i < 6; ++i) q[i] = degree ? radians(v[i]) : v[i];
    return q;
  }

  // A frame: a 4x4 matrix, or {position: [x, y, z] mm, rotation: [rx, ry, rz] degrees}
  // (turned about the fixed X, then Y, then Z axes).
  Pose frame(const YAML::Node& node, const std::string& key) const {
    if (node.IsSequence()) {
      if (node.size() != 4) fail(key + ": a matrix is 4 rows of 4 numbers");
      Eigen::Matrix4d m;
      for (int r = 0; r < 4; ++r) {
        const std::vector<double> row = numbers(node[r], 4, key);
        for (int c = 0; c < 4; ++c) m(r, c) = row[c];
      }
      if (!isRigid(m)) fail(key + ": not a rigid transform");
      return Pose(m);
    }
    if (!node.IsMap()) fail(key + ": expected {position: [x, y, z], rotation: [rx, ry, rz]}");
    for (const auto& item : node) {
      const std::string field = item.first.as<std::string>();
      if (field != "position" && field != "rotation") fail(key + ": unknown field '" + field + "'");
    }
    Pose pose = Pose::Identity();
    if (node["position"]) pose.translation() = vector(node["position"], key + ".position");
    if (node["rotation"]) {
      const Vec3 r = vector(node["rotation"], key + ".rotation") * radians(1);
      pose.linear() =
          (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
              .toRotationMatrix();
    }
    return pose;
  }

  RobotModel robot(const YAML::Node& node) const {
    const std::string key = "cell.robot";
    if (!node.IsMap()) fail(key + " must be a mapping");
    static const std::set<std::string> fields = {
        "preset", "a1",   "a2",      "b",          "c1",          "c2",
        "c3",     "c4",   "offsets", "signs",      "lower",       "upper",
        "speeds", "base", "name",    "link_radii", "link_meshes", "accelerations"};
    for (const auto& item : node)
      if (!fields.count(item.first.as<std::string>()))
        fail(key + ": unknown field '" + item.first.as<std::string>() + "'");
    RobotModel r;
    if (node["preset"]) {
      const std::string preset = scalar<std::string>(node["preset"], key + ".preset");
      const std::vector<std::string> known = robotPresets();
      if (std::find(known.begin(), known.end(), preset) == known.end()) {
        std::string list;
        for (const std::string& name : known) list += (list.empty() ? "" : ", ") + name;
        fail(key + ".preset: unknown robot '" + preset + "' (known: " + list + ")");
      }
      r = robotPreset(preset, path_);
    } else {
      for (const char* needed : {"a1", "a2", "b", "c1", "c2", "c3", "c4", "lower", "upper"})
        if (!node[needed])
          fail(key +
               ": give a preset, or every OPW parameter (a1, a2, b, c1, c2, c3, c4) and "
               "the joint limits (lower, upper); missing '" +
               std::string(needed) + "'");
      r.name = node["name"] ? scalar<std::string>(node["name"], key + ".name") : "custom";
      r.speeds.fill(radians(100));  // unless given: 100°/s on every joint
    }
    double* lengths[] = {&r.a1, &r.a2, &r.b, &r.c1, &r.c2, &r.c3, &r.c4};
    const char* names[] = {"a1", "a2", "b", "c1", "c2", "c3", "c4"};
    for (int i = 0; i < 7; ++i)
      if (node[names[i]] && r.offset_wrist)
        fail(key + "." + names[i] + ": an ortho-parallel length, but " + r.name +
             " has an offset wrist (its lengths come with the preset)");
    for (int i = 0; i < 7; ++i)
      if (node[names[i]]) *lengths[i] = scalar<double>(node[names[i]], key + "." + names[i]);
    if (node["offsets"]) r.offsets = joints(node["offsets"], key + ".offsets");
    if (node["lower"]) r.lower = joints(node["lower"], key + ".lower");
    if (node["upper"]) r.upper = joints(node["upper"], key + ".upper");
    if (node["speeds"]) r.speeds = joints(node["speeds"], key + ".speeds");
    if (!node["preset"] || node["speeds"]) r.accelerations = rampAccelerations(r.speeds);
    if (node["accelerations"])
      r.accelerations = joints(node["accelerations"], key + ".accelerations");
    if (node["link_radii"]) {
      const std::vector<double> radii = numbers(node["link_radii"], 3, key + ".link_radii");
      for (int i = 0; i < 3; ++i) {
        if (!(radii[i] > 0))
          fail(key +
               ".link_radii: the upper arm's, forearm's and wrist's radii must be positive (mm)");
        r.link_radii[i] = radii[i];
      }
    }
    if (node["signs"]) {
      const Joints signs = joints(node["signs"], key + ".signs", false);
      for (int i = 0; i < 6; ++i) {
        if (signs[i] != 1 && signs[i] != -1) fail(key + ".signs: each sign is 1 or -1");
        r.signs[i] = static_cast<int>(signs[i]);
      }
    }
    return r;
  }

  RotaryTable table(const YAML::Node& node) const {
    const std::string key = "cell.table";
    if (!node.IsMap()) fail(key + " must be a mapping");
    for (const auto& item : node) {
      const std::string field = item.first.as<std::string>();
      if (field != "origin" && field != "axis" && field != "range" && field != "step" &&
          field != "speed" && field != "acceleration" && field != "unit")
        fail(key + ": unknown field '" + field + "'");
    }
    RotaryTable t;
    if (node["origin"]) t.origin = vector(node["origin"], key + ".origin");
    if (node["axis"]) t.axis = vector(node["axis"], key + ".axis").normalized();
    if (node["range"]) {
      const std::vector<double> range = numbers(node["range"], 2, key + ".range");
      t.lower = radians(range[0]);
      t.upper = radians(range[1]);
    }
    if (node["step"]) t.step = radians(scalar<double>(node["step"], key + ".step"));
    if (node["speed"]) t.speed = radians(scalar<double>(node["speed"], key + ".speed"));
    if (node["acceleration"])
      t.acceleration = radians(scalar<double>(node["acceleration"], key + ".acceleration"));
    if (node["unit"]) t.unit = scalar<std::string>(node["unit"], key + ".unit");
    return t;
  }

  Task task(const YAML::Node& node, std::size_t index) const {
    const std::string key = "tasks[" + std::to_string(index + 1) + "]";
    if (!node.IsMap() || !node["type"])
      fail(key + " needs a type (gdt, trim, surface, global or points)");
    Task task;
    const std::string type = scalar<std::string>(node["type"], key + ".type");
    if (type == "gdt")
      task.type = TaskType::Gdt;
    else if (type == "trim")
      task.type = TaskType::Trim;
    else if (type == "surface")
      task.type = TaskType::Surface;
    else if (type == "global")
      task.type = TaskType::Global;
    else if (type == "points")
      task.type = TaskType::Points;
    else
      fail(key + ": unknown task type '" + type + "'");
    for (const auto& item : node) {
      const std::string field = item.first.as<std::string>();
      if (field != "type" && field != "faces" && field != "file")
        fail(key + ": unknown field '" + field + "'");
    }
    if (node["faces"] && (task.type == TaskType::Global || task.type == TaskType::Points))
      fail(key + ": a " + type + " task takes no faces (" +
           (task.type == TaskType::Global ? "it covers every face but the fixture's; "
                                            "a surface or trim task takes chosen faces)"
                                          : "its points come from its file)"));
    task.faces = faces(node["faces"], key + ".faces");
    if (task.type == TaskType::Points) {
      if (!node["file"]) fail(key + ": a points task needs file: control_points.csv");
      task.points_file = resolvePath(scalar<std::string>(node["file"], key + ".file"));
      task.points = readPointsCsv(task.points_file);
    } else if (node["file"]) {
      fail(key + ": only a points task takes a file");
    }
    return task;
  }

 private:
  std::string path_;
};

// What a spec may hold, counted as its YAML nodes with every alias expanded, and how deep
// they may nest: far beyond any spec of a real part, and short of what a few aliases that
// repeat one another (a "billion laughs") or a runaway nesting would make the reader walk.
constexpr std::size_t kMostSpecNodes = 1000000;
constexpr int kDeepestSpecNesting = 64;

// Fails on the first mapping anywhere under `node` that gives a key twice (YAML forbids
// it; the reader would silently take one of them), and on a document larger or deeper than
// the limits above. `visited` counts the nodes walked so far.
void rejectDuplicateKeys(const YAML::Node& node, const SpecReader& reader, const std::string& where,
                         std::size_t& visited, int depth = 0) {
  if (++visited > kMostSpecNodes)
    reader.fail(
        fmt::format("more than {} values once its aliases are expanded (aliases that "
                    "repeat one another?)",
                    kMostSpecNodes));
  if (depth > kDeepestSpecNesting)
    reader.fail(fmt::format("{} is nested more than {} levels deep", where, kDeepestSpecNesting));
  if (node.IsSequence())
    for (std::size_t i = 0; i < node.size(); ++i)
      rejectDuplicateKeys(node[i], reader, where + "[" + std::to_string(i + 1) + "]", visited,
                          depth + 1);
  if (!node.IsMap()) return;
  std::set<std::string> keys;
  for (const auto& item : node) {
    const std::string key = item.first.Scalar();
    if (!keys.insert(key).second) reader.fail("key '" + key + "' given twice in " + where);
    rejectDuplicateKeys(item.second, reader, key, visited, depth + 1);
  }
}

void checkKeys(const YAML::Node& node, const std::set<std::string>& allowed,
               const SpecReader& reader, const std::string& section) {
  if (!node.IsMap()) reader.fail(section + " must be a mapping");
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    if (!allowed.count(key)) reader.fail("unknown key '" + key + "' in " + section);
  }
}

CycleSettings readCycle(const YAML::Node& node, const SpecReader& reader) {
  checkKeys(node, {"settle", "handshake", "speed", "acceleration", "turn_over"}, reader, "cycle");
  CycleSettings c;
  reader.read(node, "cycle", "settle", c.settle);
  reader.read(node, "cycle", "handshake", c.handshake);
  reader.read(node, "cycle", "speed", c.speed);
  reader.read(node, "cycle", "acceleration", c.acceleration);
  reader.read(node, "cycle", "turn_over", c.turn_over);
  validate(c, reader.path());
  return c;
}

// planner.coverage: one share for every task's samples but the priority ones, or a
// mapping of shares by `priority`, `others` and task type; each within (0, 1].
CoverageTargets readCoverage(const YAML::Node& node, const SpecReader& reader) {
  CoverageTargets targets;
  auto share = [&](const YAML::Node& value, const std::string& key) {
    const double v = reader.scalar<double>(value, key);
    if (!(v > 0 && v <= 1)) reader.fail(key + " must be a share within (0, 1]");
    return v;
  };
  if (node.IsScalar()) {
    targets.others = share(node, "planner.coverage");
    return targets;
  }
  checkKeys(node, {"priority", "others", "gdt", "trim", "surface", "global", "points"}, reader,
            "planner.coverage");
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    const double v = share(item.second, "planner.coverage." + key);
    if (key == "priority")
      targets.priority = v;
    else if (key == "others")
      targets.others = v;
    else
      for (TaskType type : kTaskTypes)
        if (key == toString(type)) targets.tasks[type] = v;
  }
  return targets;
}

// planner.`key`, one of `two` names: the first is Enum's first value, the second its second.
template <class Enum>
void readChoice(const YAML::Node& node, const std::string& key,
                const std::array<std::string, 2>& two, const SpecReader& reader, Enum& value) {
  const YAML::Node given = node[key];
  if (!given) return;
  const auto name = reader.scalar<std::string>(given, "planner." + key);
  if (name != two[0] && name != two[1])
    reader.fail("planner." + key + " must be " + two[0] + " or " + two[1] + ", not '" + name + "'");
  value = static_cast<Enum>(name == two[0] ? 0 : 1);
}

PlannerSettings readPlanner(const YAML::Node& node, const SpecReader& reader) {
  checkKeys(
      node,
      {"seed", "vm_step", "tilt", "max_failures", "sweep_overlap", "rotations", "rescue", "anchors",
       "pool_rotations", "selection_nodes", "selection_seconds", "most_views", "capable_ratio",
       "evaluation_spacing", "lift_capability", "coverage", "objective", "aim"},
      reader, "planner");
  PlannerSettings p;
  reader.read(node, "planner", "seed", p.seed);
  reader.read(node, "planner", "vm_step", p.vm_step);
  reader.read(node, "planner", "max_failures", p.max_failures);
  reader.read(node, "planner", "sweep_overlap", p.sweep_overlap);
  reader.read(node, "planner", "rotations", p.rotations);
  reader.read(node, "planner", "anchors", p.anchors);
  reader.read(node, "planner", "pool_rotations", p.pool_rotations);
  reader.read(node, "planner", "selection_nodes", p.selection_nodes);
  reader.read(node, "planner", "selection_seconds", p.selection_seconds);
  reader.read(node, "planner", "most_views", p.most_views);
  reader.read(node, "planner", "capable_ratio", p.capability.capable_ratio);
  reader.read(node, "planner", "evaluation_spacing", p.capability.evaluation_spacing);
  reader.read(node, "planner", "lift_capability", p.lift_capability);
  if (const YAML::Node tilt = node["tilt"]) {
    if (!tilt.IsSequence() || tilt.size() != 2)
      reader.fail("planner.tilt must be [min, max] in degrees");
    p.tilt_min = reader.scalar<double>(tilt[0], "planner.tilt");
    p.tilt_max = reader.scalar<double>(tilt[1], "planner.tilt");
  }
  if (const YAML::Node coverage = node["coverage"]) p.coverage = readCoverage(coverage, reader);
  readChoice(node, "objective", {"views", "cycle_time"}, reader, p.objective);
  readChoice(node, "aim", {"samples", "characteristics"}, reader, p.aim);
  if (const YAML::Node rescue = node["rescue"]) {
    checkKeys(rescue, {"step", "rotations", "narrow"}, reader, "planner.rescue");
    reader.read(rescue, "planner.rescue", "step", p.rescue_step);
    reader.read(rescue, "planner.rescue", "rotations", p.rescue_rotations);
    reader.read(rescue, "planner.rescue", "narrow", p.rescue_narrow);
  }
  // A visibility map has a cell per vm_step² of the hemisphere, for every sample.
  if (!(p.vm_step >= 1 && p.vm_step <= 45))
    reader.fail("planner.vm_step must be within [1, 45] degrees");
  if (!(p.tilt_min >= 0 && p.tilt_min <= p.tilt_max && p.tilt_max < 90))
    reader.fail("planner.tilt must be [min, max] with 0 <= min <= max < 90 degrees");
  if (p.max_failures < 1) reader.fail("planner.max_failures must be at least 1");
  if (!(p.sweep_overlap >= 0 && p.sweep_overlap <= 0.8))
    reader.fail("planner.sweep_overlap must be within [0, 0.8]");
  if (p.rotations < 1 || p.rotations > 36 || p.rescue_rotations < 1 || p.rescue_rotations > 36)
    reader.fail("planner.rotations and planner.rescue.rotations must be within [1, 36]");
  if (p.anchors < 0 || p.anchors > 100000)
    reader.fail("planner.anchors must be within [0, 100000]");
  if (p.pool_rotations < 1 || p.pool_rotations > 36)
    reader.fail("planner.pool_rotations must be within [1, 36]");
  if (p.selection_nodes < 0) reader.fail("planner.selection_nodes must not be negative");
  if (!(p.selection_seconds >= 0 && p.selection_seconds <= 3600))
    reader.fail("planner.selection_seconds must be within [0, 3600]");
  if (p.most_views < 1) reader.fail("planner.most_views must be at least 1");
  if (!(p.capability.capable_ratio >= 1 && p.capability.capable_ratio <= 100))
    reader.fail("planner.capable_ratio must be within [1, 100]");
  if (!(p.capability.evaluation_spacing >= 0 && p.capability.evaluation_spacing <= 100))
    reader.fail("planner.evaluation_spacing must be within [0, 100] mm");
  if (!(p.rescue_step >= 1 && p.rescue_step <= 45))
    reader.fail("planner.rescue.step must be within [1, 45] degrees");
  return p;
}

// part: file and rest.
void readPart(const YAML::Node& part, const SpecReader& reader, Spec& spec) {
  checkKeys(part, {"file", "rest"}, reader, "part");
  if (part["file"])
    spec.part_file = reader.resolvePath(reader.scalar<std::string>(part["file"], "part.file"));
  if (const YAML::Node rest = part["rest"]) {
    if (rest.IsScalar() && rest.as<std::string>() == "auto") {
      spec.rest_auto = true;
    } else if (rest.IsScalar() && rest.as<std::string>() == "all") {
      spec.rest_all = true;
    } else if (int face = 0; rest.IsScalar() && YAML::convert<int>::decode(rest, face)) {
      if (face < 1) reader.fail("part.rest: face ids start at 1");
      spec.rest_face = face;
    } else if (rest.IsSequence() && rest.size() == 4) {
      Eigen::Matrix4d m;
      for (int r = 0; r < 4; ++r) {
        if (!rest[r].IsSequence() || rest[r].size() != 4)
          reader.fail("part.rest: a matrix is 4 rows of 4 numbers");
        for (int c = 0; c < 4; ++c) m(r, c) = reader.scalar<double>(rest[r][c], "part.rest");
      }
      if (!isRigid(m)) reader.fail("part.rest: not a rigid transform");
      spec.rest_pose = Pose(m);
    } else {
      reader.fail("part.rest: expected auto, all, a face id or a 4x4 matrix");
    }
  }
}

// markers.on: plate, table, part, both (plate and part) or fixture, or a list of them.
void readMarkersOn(const YAML::Node& on, const SpecReader& reader, Spec& spec) {
  std::vector<std::string> places;
  if (on.IsSequence()) {
    for (const YAML::Node& item : on)
      places.push_back(reader.scalar<std::string>(item, "markers.on"));
  } else {
    places.push_back(reader.scalar<std::string>(on, "markers.on"));
  }
  constexpr const char* kPlaces = "plate, table, part, both or fixture";
  if (places.empty()) reader.fail(fmt::format("markers.on: expected {}", kPlaces));
  spec.markers_on_plate = spec.markers_on_table = spec.markers_on_part = spec.markers_on_fixture =
      false;
  for (const std::string& place : places) {
    if (place != "plate" && place != "table" && place != "part" && place != "both" &&
        place != "fixture")
      reader.fail(fmt::format("markers.on: expected {}, got '{}'", kPlaces, place));
    spec.markers_on_plate |= place == "plate" || place == "both";
    spec.markers_on_table |= place == "table";
    spec.markers_on_part |= place == "part" || place == "both";
    spec.markers_on_fixture |= place == "fixture";
  }
  if (spec.markers_on_plate && spec.markers_on_table)
    reader.fail("markers.on: plate and table both put the grid around the part; give one");
}

// markers: {file, on}: what carries the CSV's markers, plate (the default), table or part.
void readMarkersFile(const YAML::Node& markers, const SpecReader& reader, Spec& spec) {
  spec.markers_file =
      reader.resolvePath(reader.scalar<std::string>(markers["file"], "markers.file"));
  requireInputFile(spec.markers_file);  // also when registration is off: named, it must be
  if (!markers["on"]) return;
  const auto on = reader.scalar<std::string>(markers["on"], "markers.on");
  if (on == "plate")
    spec.markers_file_on = MarkerCarrier::Plane;
  else if (on == "table")
    spec.markers_file_on = MarkerCarrier::Table;
  else if (on == "part")
    spec.markers_file_on = MarkerCarrier::Part;
  else
    reader.fail("markers.on: a file's markers lie on plate, table or part, not '" + on + "'");
}

// fixtures: a list of {file, placement, frame: part or world, markers: CSV}.
std::vector<FixtureModel> readFixtures(const YAML::Node& node, const SpecReader& reader) {
  if (!node.IsSequence()) reader.fail("fixtures must be a list of {file, placement, frame}");
  std::vector<FixtureModel> fixtures;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string key = "fixtures[" + std::to_string(i + 1) + "]";
    const YAML::Node item = node[i];
    if (!item.IsMap()) reader.fail(key + ": expected {file, placement, frame, markers}");
    checkKeys(item, {"file", "placement", "frame", "markers"}, reader, key);
    if (!item["file"]) reader.fail(key + ": needs a file (STEP, IGES, BREP or a mesh)");
    FixtureModel fixture;
    fixture.file = reader.resolvePath(reader.scalar<std::string>(item["file"], key + ".file"));
    if (item["placement"]) fixture.placement = reader.frame(item["placement"], key + ".placement");
    if (item["frame"]) {
      const auto frame = reader.scalar<std::string>(item["frame"], key + ".frame");
      if (frame != "part" && frame != "world")
        reader.fail(key + ".frame: expected part or world, got '" + frame + "'");
      fixture.in_world = frame == "world";
    }
    if (item["markers"])
      fixture.markers_file =
          reader.resolvePath(reader.scalar<std::string>(item["markers"], key + ".markers"));
    if (!fixture.markers_file.empty()) requireInputFile(fixture.markers_file);
    fixtures.push_back(fixture);
  }
  return fixtures;
}

// markers: a CSV of markers (or {file, on}), or a generated grid; either with the diameter
// a marker covers.
void readMarkers(const YAML::Node& markers, const SpecReader& reader, Spec& spec) {
  if (markers.IsMap() && markers["diameter"]) {
    spec.marker_diameter = reader.scalar<double>(markers["diameter"], "markers.diameter");
    if (!(spec.marker_diameter >= 0 && spec.marker_diameter <= 100))
      reader.fail("markers.diameter must be from 0 to 100 mm");
  }
  if (markers.IsMap() && markers["file"]) {
    checkKeys(markers, {"file", "on", "diameter"}, reader, "markers");
    readMarkersFile(markers, reader, spec);
  } else if (markers.IsMap()) {
    checkKeys(markers, {"grid", "margin", "on", "diameter"}, reader, "markers");
    if (const YAML::Node on = markers["on"]) readMarkersOn(on, reader, spec);
    if (!markers["grid"]) reader.fail("markers: a generated grid needs grid: <step in mm>");
    spec.marker_grid = reader.scalar<double>(markers["grid"], "markers.grid");
    if (markers["margin"])
      spec.marker_margin = reader.scalar<double>(markers["margin"], "markers.margin");
    if (!(spec.marker_grid > 0)) reader.fail("markers.grid must be a positive step in mm");
    if (!(spec.marker_margin >= 0)) reader.fail("markers.margin must not be negative");
  } else {
    spec.markers_file = reader.resolvePath(reader.scalar<std::string>(markers, "markers"));
    requireInputFile(spec.markers_file);  // also when registration is off: named, it must be
  }
}

RegistrationOptions readRegistration(const YAML::Node& node, const SpecReader& reader,
                                     const std::string& path) {
  checkKeys(node,
            {"method", "robot_accuracy", "required", "min_markers", "marker_spread", "marker_sigma",
             "min_overlap", "max_condition", "point_spacing", "verify", "aligned_as_taken",
             "cloud_spacing", "perturbation", "tolerance", "bridging", "max_bridging_views"},
            reader, "registration");
  RegistrationOptions r;
  if (const YAML::Node method = node["method"]) {
    const auto name = reader.scalar<std::string>(method, "registration.method");
    const auto found = std::find_if(kRegistrationModes.begin(), kRegistrationModes.end(),
                                    [&](RegistrationMode m) { return toString(m) == name; });
    if (found == kRegistrationModes.end())
      reader.fail(
          "registration.method must be markers, geometry, robot or reference_points, not '" + name +
          "'");
    r.method = *found;
  }
  reader.read(node, "registration", "robot_accuracy", r.robot_accuracy);
  reader.read(node, "registration", "required", r.required);
  reader.read(node, "registration", "min_markers", r.min_markers);
  reader.read(node, "registration", "marker_spread", r.marker_spread);
  reader.read(node, "registration", "marker_sigma", r.marker_sigma);
  reader.read(node, "registration", "min_overlap", r.min_overlap);
  reader.read(node, "registration", "max_condition", r.max_condition);
  reader.read(node, "registration", "point_spacing", r.point_spacing);
  reader.read(node, "registration", "verify", r.verify);
  reader.read(node, "registration", "aligned_as_taken", r.aligned_as_taken);
  reader.read(node, "registration", "cloud_spacing", r.cloud_spacing);
  reader.read(node, "registration", "tolerance", r.tolerance);
  reader.read(node, "registration", "bridging", r.bridging);
  reader.read(node, "registration", "max_bridging_views", r.max_bridging_views);
  if (const YAML::Node perturbation = node["perturbation"]) {
    if (!perturbation.IsSequence() || perturbation.size() != 2)
      reader.fail("registration.perturbation must be [mm, degrees]");
    r.perturbation = reader.scalar<double>(perturbation[0], "registration.perturbation");
    r.perturbation_angle = reader.scalar<double>(perturbation[1], "registration.perturbation");
  }
  validate(r, path);
  return r;
}

// cell: working plane, robot, mount, table, clearance.
// cell.home (joints, degrees, within the robot's limits), cell.approach (mm) and
// cell.joint_margin (degrees). cell.motion_step, an angle step of earlier versions, is
// refused: moves are checked at half the clearance (docs/cell.md).
void readMotion(const YAML::Node& cell, const SpecReader& reader, Cell& c) {
  if (cell["home"]) {
    const Joints home = reader.joints(cell["home"], "cell.home");
    c.home = home;
  }
  reader.read(cell, "cell", "approach", c.approach);
  if (cell["motion_step"])
    reader.fail(
        "cell.motion_step is no longer a setting: moves are checked so that no point moves "
        "more than half cell.clearance between configurations; remove it");
  if (cell["joint_margin"])
    c.joint_margin = radians(reader.scalar<double>(cell["joint_margin"], "cell.joint_margin"));
}

// cell.tool: {mass: kg, centre: [x, y, z] mm in the flange frame, inertia: [Jx, Jy, Jz]
// kg·m² about the centre}.
ToolLoad readTool(const YAML::Node& node, const SpecReader& reader) {
  checkKeys(node, {"mass", "centre", "inertia"}, reader, "cell.tool");
  ToolLoad tool;
  reader.read(node, "cell.tool", "mass", tool.mass);
  if (node["centre"]) {
    const std::vector<double> c = reader.numbers(node["centre"], 3, "cell.tool.centre");
    tool.centre = Vec3(c[0], c[1], c[2]);
  }
  if (node["inertia"]) {
    const std::vector<double> j = reader.numbers(node["inertia"], 3, "cell.tool.inertia");
    tool.inertia = Vec3(j[0], j[1], j[2]);
  }
  return tool;
}

// cell.signals: {view, trigger, acknowledge, table: {angle, move, ready}}, whole numbers;
// timeout, seconds.
CellSignals readSignals(const YAML::Node& node, const SpecReader& reader) {
  checkKeys(node, {"view", "trigger", "acknowledge", "table", "timeout"}, reader, "cell.signals");
  auto number = [&](const YAML::Node& at, const std::string& section, const char* key, int& into) {
    reader.read(at, section, key, into);
  };
  CellSignals signals;
  number(node, "cell.signals", "view", signals.view);
  number(node, "cell.signals", "trigger", signals.trigger);
  number(node, "cell.signals", "acknowledge", signals.acknowledge);
  reader.read(node, "cell.signals", "timeout", signals.timeout);
  if (const YAML::Node table = node["table"]) {
    checkKeys(table, {"angle", "move", "ready"}, reader, "cell.signals.table");
    for (const char* key : {"angle", "move", "ready"})
      if (!table[key]) reader.fail(std::string("cell.signals.table needs '") + key + "'");
    TableSignals& t = signals.table.emplace();
    number(table, "cell.signals.table", "angle", t.angle);
    number(table, "cell.signals.table", "move", t.move);
    number(table, "cell.signals.table", "ready", t.ready);
  }
  return signals;
}

void readCell(const YAML::Node& cell, const SpecReader& reader, Spec& spec) {
  checkKeys(cell,
            {"working_plane", "robot", "mount", "table", "clearance", "tool", "signals", "home",
             "approach", "motion_step", "joint_margin"},
            reader, "cell");
  if (cell["working_plane"])
    spec.working_plane = reader.scalar<bool>(cell["working_plane"], "cell.working_plane");
  if (cell["robot"]) {
    Cell c;
    c.robot = reader.robot(cell["robot"]);
    if (cell["robot"]["base"]) c.base = reader.frame(cell["robot"]["base"], "cell.robot.base");
    if (const YAML::Node meshes = cell["robot"]["link_meshes"]) {
      if (!meshes.IsSequence() || meshes.size() != 3)
        reader.fail(
            "cell.robot.link_meshes: give the upper arm's, the forearm's and the "
            "wrist's mesh files, in the base frame at the zero pose");
      for (const YAML::Node& file : meshes) {
        const std::string mesh_path =
            reader.resolvePath(reader.scalar<std::string>(file, "cell.robot.link_meshes"));
        TriangleMesh mesh = importPart(mesh_path).mesh;
        if (mesh.empty()) throw InputError(mesh_path, "the link mesh has no triangles");
        c.link_meshes.push_back(std::move(mesh));
      }
    }
    // Default mount: the camera 150 mm out along the flange's axis, looking along it.
    c.mount.translation() = Vec3(0, 0, 150);
    if (cell["mount"]) c.mount = reader.frame(cell["mount"], "cell.mount");
    if (cell["table"]) c.table = reader.table(cell["table"]);
    if (cell["clearance"]) {
      c.clearance = reader.scalar<double>(cell["clearance"], "cell.clearance");
    }
    readMotion(cell, reader, c);
    if (cell["tool"]) c.tool = readTool(cell["tool"], reader);
    if (cell["signals"]) c.signals = readSignals(cell["signals"], reader);
    validate(c, reader.path());
    spec.cell = c;
  } else if (cell["mount"] || cell["table"] || cell["clearance"] || cell["tool"] ||
             cell["signals"] || cell["home"] || cell["approach"] || cell["motion_step"] ||
             cell["joint_margin"]) {
    reader.fail("cell: a mount or a table needs a robot (cell.robot)");
  }
}

// The spec of the YAML document `root`, read from `path`.
Spec specFromYaml(const YAML::Node& root, const std::string& path) {
  Spec spec = defaultSpec();
  spec.source = path;
  if (root.IsNull()) return spec;
  const SpecReader reader(path);
  if (!root.IsMap())
    reader.fail("a spec is a mapping of sections (scanner, part, roles, tasks, ...)");
  try {
    std::size_t visited = 0;
    rejectDuplicateKeys(root, reader, "the spec", visited);
    checkKeys(root,
              {"scanner", "part", "roles", "gdt", "markers", "fixtures", "registration", "tasks",
               "planner", "cell", "cycle"},
              reader, "the spec");
    if (root["scanner"]) spec.scanner = scannerFromYaml(root, path);
    if (const YAML::Node part = root["part"]) readPart(part, reader, spec);
    if (const YAML::Node roles = root["roles"]) {
      checkKeys(roles, {"priority", "fixture", "specular"}, reader, "roles");
      spec.priority = reader.faces(roles["priority"], "roles.priority");
      spec.fixture = reader.faces(roles["fixture"], "roles.fixture");
      spec.specular = reader.faces(roles["specular"], "roles.specular");
    }
    if (const YAML::Node gdt = root["gdt"]) {
      const std::string value = reader.scalar<std::string>(gdt, "gdt");
      if (value != "from-file" && value != "all" && value != "none")
        reader.fail("gdt: expected from-file, all or none, got '" + value + "'");
      spec.gdt_from_file = value != "none";
      spec.gdt_dimensions = value == "all";
    }
    if (const YAML::Node markers = root["markers"]) readMarkers(markers, reader, spec);
    if (const YAML::Node fixtures = root["fixtures"])
      spec.fixtures = readFixtures(fixtures, reader);
    if (const YAML::Node node = root["registration"])
      spec.registration = readRegistration(node, reader, path);
    if (const YAML::Node tasks = root["tasks"]) {
      if (!tasks.IsSequence() || tasks.size() == 0) reader.fail("tasks must be a non-empty list");
      spec.tasks.clear();
      for (std::size_t i = 0; i < tasks.size(); ++i) spec.tasks.push_back(reader.task(tasks[i], i));
    } else if (spec.gdt_from_file) {
      spec.tasks = {Task{TaskType::Gdt, {}, {}, {}}};  // gdt: from-file alone asks for a gdt task
    }
    if (const YAML::Node planner = root["planner"]) spec.planner = readPlanner(planner, reader);
    if (const YAML::Node cell = root["cell"]) readCell(cell, reader, spec);
    if (const YAML::Node cycle = root["cycle"]) spec.cycle = readCycle(cycle, reader);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.what());
  }
  return spec;
}

}  // namespace

Spec loadSpec(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  return specFromText({std::istreambuf_iterator<char>(in), {}}, path);
}

Spec specFromText(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = loadOneDocument(text, source, "a spec");
  } catch (const YAML::Exception& e) {
    throw InputError(source, "not valid YAML: " + std::string(e.what()));
  }
  Spec spec = specFromYaml(root, source);
  spec.text = text;
  return spec;
}

Spec planSpec(const Plan& plan, const std::string& plan_file) {
  if (!plan.spec) return defaultSpec();
  Spec spec;
  try {
    spec = plan.spec->text.empty() ? defaultSpec() : specFromText(plan.spec->text, plan.spec->file);
  } catch (const InputError& e) {
    throw InputError(plan_file,
                     "the spec it was made with, " + plan.spec->file + ": " + e.reason());
  }
  try {
    if (!plan.spec->rest.empty()) setRest(spec, plan.spec->rest, "spec.rest");
  } catch (const UsageError& e) {
    throw InputError(plan_file, e.what());
  }
  return spec;
}

}  // namespace scanplan
