#include "io/json_values.h"

#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/views_json.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>

namespace scanplan {

using nlohmann::json;

ViewsFile readViews(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path);
  const json root = detail::parseJson(in, path);
  ViewsFile file;
  const json* views = &root;
  if (root.is_object()) {
    file.plan = root.contains("format") && root["format"] == "scanplan.plan";
    if (!root.contains("views")) throw InputError(path, "no 'views' array");
    views = &root["views"];
    if (root.contains("part") && root["part"].contains("part_to_world"))
      file.part_to_world.matrix() =
          detail::matrixFrom(root["part"]["part_to_world"], path, "part.part_to_world");
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
      if (view.id < 1) throw InputError(path, what + ": ids must be positive");
    }
    if (!ids.insert(view.id).second) throw InputError(path, what + ": id is used twice");
    if (!v.contains("camera_to_world")) throw InputError(path, what + ": no camera_to_world");
    view.camera_to_world.matrix() =
        detail::matrixFrom(v["camera_to_world"], path, what + " camera_to_world");
    view.target = v.contains("target") ? detail::vectorFrom(v["target"], path, what + " target")
                                       : view.camera();
    if (v.contains("task") && v["task"].is_string()) view.task = v["task"].get<std::string>();
    file.views.push_back(view);
  }
  return file;
}

}  // namespace scanplan
