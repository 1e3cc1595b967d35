// The inspection-spec editor: the page web/src/editor.html with its script (three.js and
// web/src/editor.js) and the part's data inlined (io/page.h): faces with their exact
// elementary surfaces, characteristics, rest orientations, scanner presets, and the spec
// it starts from.

#include "core/assets.h"
#include "io/page.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/localization.h>
#include <scanplan/core/errors.h>
#include <scanplan/editor/editor.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/sampling/sampling.h>
#include <scanplan/spec/spec.h>

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <filesystem>

namespace scanplan {
namespace {

using json = nlohmann::ordered_json;  // the spec's document keeps its order

json vec(const Vec3& v) { return detail::vec<json>(v); }

// Face `id`'s surface where it is elementary (plane, cylinder, cone, sphere, torus), for the
// page to snap clicked points onto it exactly; null for other surfaces and mesh parts. A
// plane's axis is the face's outward normal; a cone's radius is R + h tan(semi_angle) at
// height h along the axis.
json surfaceJson(const Part& part, int id) {
  const std::optional<ElementarySurface> s = elementarySurface(part, id);
  if (!s) return nullptr;
  switch (s->type) {
    case SurfaceType::Plane:
      return {{"type", "plane"}, {"origin", vec(s->origin)}, {"axis", vec(s->axis)}};
    case SurfaceType::Cylinder:
      return {{"type", "cylinder"},
              {"origin", vec(s->origin)},
              {"axis", vec(s->axis)},
              {"radius", s->radius}};
    case SurfaceType::Cone:
      return {{"type", "cone"},
              {"origin", vec(s->origin)},
              {"axis", vec(s->axis)},
              {"radius", s->radius},
              {"semi_angle", s->semi_angle}};
    case SurfaceType::Sphere:
      return {{"type", "sphere"}, {"origin", vec(s->origin)}, {"radius", s->radius}};
    case SurfaceType::Torus:
      return {{"type", "torus"},
              {"origin", vec(s->origin)},
              {"axis", vec(s->axis)},
              {"radius", s->radius},
              {"minor_radius", s->minor_radius}};
    default: return nullptr;
  }
}

json facesJson(const Part& part) {
  json faces = json::array();
  for (const Face& f : part.faces)
    faces.push_back({{"id", f.id},
                     {"type", toString(f.type)},
                     {"name", f.name},
                     {"area", f.area},
                     {"surface", surfaceJson(part, f.id)}});
  return faces;
}

json characteristicsJson(const Part& part) {
  json list = json::array();
  for (const Characteristic& c : characteristics(part.gdt))
    list.push_back(json(characteristicJson(c)));
  return list;
}

json matrixJson(const Pose& pose) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
  return rows;
}

// The flat face of the part that `rest` stands on, as part.rest takes it (the largest, when
// several touch the plane), or 0 when the hull face it rests on holds no face of the part:
// a plane facing down whose triangles all lie on the working plane.
int restFace(const Part& part, const RestOrientation& rest) {
  const double tolerance = 1e-6 * part.bounds().diagonal();
  int best = 0;
  for (const Face& f : part.faces) {
    if (f.type != SurfaceType::Plane || f.triangle_count == 0 ||
        (best && f.area <= part.faces[best - 1].area) ||
        part.mesh.normal(f.first_triangle).dot(rest.down) < 1 - 1e-6)
      continue;
    bool on_plane = true;
    for (int t = f.first_triangle; on_plane && t < f.first_triangle + f.triangle_count; ++t)
      for (int k = 0; k < 3; ++k)
        on_plane &=
            std::abs((rest.part_to_world * part.mesh.vertices[part.mesh.triangles[t][k]]).z()) <=
            tolerance;
    if (on_plane) best = f.id;
  }
  return best;
}

// The rest orientations, steadiest first; none for a part without volume.
json restsJson(const Part& part) {
  json list = json::array();
  std::vector<RestOrientation> rests;
  try {
    rests = restOrientations(part);
  } catch (const InputError&) {
    return list;
  }
  for (const RestOrientation& r : rests)
    list.push_back({{"down", vec(r.down)},
                    {"part_to_world", matrixJson(r.part_to_world)},
                    {"margin", r.margin},
                    {"contact_area", r.contact_area},
                    {"face", restFace(part, r)}});
  return list;
}

// A YAML node as JSON: plain scalars that read as numbers, true/false or null become them,
// the rest strings (quoted scalars always).
json yamlJson(const YAML::Node& node) {
  if (node.IsMap()) {
    json object = json::object();
    for (const auto& item : node) object[item.first.as<std::string>()] = yamlJson(item.second);
    return object;
  }
  if (node.IsSequence()) {
    json array = json::array();
    for (const YAML::Node& item : node) array.push_back(yamlJson(item));
    return array;
  }
  if (!node.IsScalar()) return nullptr;
  const std::string& text = node.Scalar();
  if (node.Tag() == "!") return text;
  if (text == "true" || text == "false") return text == "true";
  if (text == "null" || text == "~") return nullptr;
  const char* end = text.data() + text.size();
  long long integer = 0;
  if (auto [at, ec] = std::from_chars(text.data(), end, integer); ec == std::errc() && at == end)
    return integer;
  double number = 0;
  if (auto [at, ec] = std::from_chars(text.data(), end, number); ec == std::errc() && at == end)
    return number;
  return text;
}

// The spec the editor starts from: its document as read (the page keeps what it does not
// edit), each task's and role's faces as ids, and the control points of its points tasks.
json specJson(const Part& part, const std::string& spec_file) {
  if (spec_file.empty()) return nullptr;
  const Spec spec = loadSpec(spec_file);
  json tasks = json::array(), points = json::array();
  for (const Task& task : spec.tasks) {
    tasks.push_back(
        {{"type", toString(task.type)}, {"faces", resolveFaces(part, task.faces, spec_file)}});
    if (task.type != TaskType::Points) continue;
    const std::vector<ControlPoint>& given = task.points;
    const std::vector<Sample> on_part = samplePoints(part, given, task.points_file);
    for (std::size_t i = 0; i < given.size(); ++i)
      points.push_back({{"position", vec(given[i].position)},
                        {"normal", vec(given[i].normal.value_or(on_part[i].normal))},
                        {"face", on_part[i].face}});
  }
  json document;
  try {
    document = yamlJson(YAML::LoadFile(spec_file));
  } catch (const YAML::Exception& e) {
    throw InputError(spec_file, "not valid YAML: " + std::string(e.what()));
  }
  return {{"file", std::filesystem::path(spec_file).filename().string()},
          {"document", document},
          {"tasks", tasks},
          {"points", points},
          {"priority", resolveFaces(part, spec.priority, spec_file)},
          {"fixture", resolveFaces(part, spec.fixture, spec_file)},
          {"specular", resolveFaces(part, spec.specular, spec_file)}};
}

}  // namespace

void writeSpecEditor(const Part& part, const std::string& spec_file, const std::string& path) {
  const Box bounds = part.bounds();
  const json data = {{"title", std::filesystem::path(part.file).filename().string()},
                     {"header", detail::headerJson(part.file, spec_file)},
                     {"mesh", json(detail::meshJson(part.mesh))},
                     {"deflection", part.linear_deflection},
                     {"bounds", {{"min", vec(bounds.min)}, {"max", vec(bounds.max)}}},
                     {"faces", facesJson(part)},
                     {"characteristics", characteristicsJson(part)},
                     {"gdt_faces", gdtFaces(part, false)},
                     {"gdt_all_faces", gdtFaces(part, true)},
                     {"rests", restsJson(part)},
                     {"presets", scannerPresetNames()},
                     {"default_preset", defaultSpec().scanner.name},
                     {"spec", specJson(part, spec_file)}};
  detail::writePage(assets::editor_html, assets::editor_js, data, path);
}

}  // namespace scanplan
