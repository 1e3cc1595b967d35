#include <scanplan/errors.h>
#include <scanplan/io/views_json.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>

namespace scanplan {

namespace {

using nlohmann::json;

Eigen::Matrix4d matrixFrom(const json& value, const std::string& path, const std::string& what) {
  if (!value.is_array() || value.size() != 4)
    throw InputError(path, what + ": expected 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    if (!value[r].is_array() || value[r].size() != 4)
      throw InputError(path, what + ": row " + std::to_string(r + 1) + " is not 4 numbers");
    for (int c = 0; c < 4; ++c) {
      if (!value[r][c].is_number())
        throw InputError(path, what + ": entry (" + std::to_string(r + 1) + ", " +
                                   std::to_string(c + 1) + ") is not a number");
      m(r, c) = value[r][c].get<double>();
    }
  }
  if (!isRigid(m))
    throw InputError(path, what +
                               ": not a rigid transform (the rotation must be orthonormal with "
                               "determinant +1 and the last row 0 0 0 1)");
  return m;
}

Vec3 vectorFrom(const json& value, const std::string& path, const std::string& what) {
  if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
      !value[2].is_number())
    throw InputError(path, what + ": expected 3 numbers");
  return Vec3(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
}

}  // namespace

ViewsFile readViews(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "no such file");
  std::ifstream in(path);
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path, std::string("not valid JSON: ") + e.what());
  }
  ViewsFile file;
  const json* views = &root;
  if (root.is_object()) {
    if (!root.contains("views")) throw InputError(path, "no 'views' array");
    views = &root["views"];
    if (root.contains("part") && root["part"].contains("part_to_world"))
      file.part_to_world.matrix() =
          matrixFrom(root["part"]["part_to_world"], path, "part.part_to_world");
  }
  if (!views->is_array()) throw InputError(path, "'views' is not an array");
  std::set<int> ids;
  for (std::size_t i = 0; i < views->size(); ++i) {
    const json& v = (*views)[i];
    std::string what = "view " + std::to_string(i + 1);
    if (!v.is_object()) throw InputError(path, what + " is not an object");
    View view;
    view.id = static_cast<int>(i + 1);
    if (v.contains("id")) {
      if (!v["id"].is_number_integer()) throw InputError(path, what + ": id is not an integer");
      view.id = v["id"].get<int>();
      what += " (id " + std::to_string(view.id) + ")";
    }
    if (!ids.insert(view.id).second) throw InputError(path, what + ": id is used twice");
    if (!v.contains("camera_to_world")) throw InputError(path, what + ": no camera_to_world");
    view.camera_to_world.matrix() =
        matrixFrom(v["camera_to_world"], path, what + " camera_to_world");
    view.target =
        v.contains("target") ? vectorFrom(v["target"], path, what + " target") : view.camera();
    if (v.contains("task") && v["task"].is_string()) view.task = v["task"].get<std::string>();
    file.views.push_back(view);
  }
  return file;
}

}  // namespace scanplan
