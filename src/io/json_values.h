#pragma once
// Values of the plan format as JSON: vectors written, and values read with errors that name
// the file and the field (private to the library).

#include <scanplan/core/errors.h>
#include <scanplan/core/view.h>

#include <nlohmann/json.hpp>

#include <istream>
#include <set>
#include <string>
#include <vector>

namespace scanplan::detail {

using nlohmann::json;

// The JSON text of `in`, refusing what nlohmann would take silently: a key given twice in
// one object (it keeps the last). \throw InputError naming `path`.
inline json parseJson(std::istream& in, const std::string& path) {
  std::vector<std::set<std::string>> keys;  // of the objects being read, outermost first
  std::string twice;
  const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.empty() &&
        !keys.back().insert(parsed.get<std::string>()).second && twice.empty())
      twice = parsed.get<std::string>();
    return true;
  };
  json root;
  try {
    root = json::parse(in, callback);
  } catch (const json::exception& e) {
    throw InputError(path, std::string("not valid JSON: ") + e.what());
  }
  if (!twice.empty())
    throw InputError(path, "the key '" + twice + "' is given twice in one object");
  return root;
}

// Refuses a key of `object` that is not among `known`, naming `where`.
inline void refuseUnknownKeys(const json& object, std::initializer_list<const char*> known,
                              const std::string& path, const std::string& where) {
  if (!object.is_object()) return;
  for (const auto& [key, value] : object.items()) {
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) throw InputError(path, where + ": unknown key '" + key + "'");
  }
}

// A vector as a JSON array of three numbers (in `Json`, nlohmann's json or ordered_json).
template <class Json = json>
Json vec(const Vec3& v) {
  return Json::array({v.x(), v.y(), v.z()});
}

// A rigid 4x4 matrix given as 4 rows of 4 numbers. \throw InputError naming `what`.
inline Eigen::Matrix4d matrixFrom(const json& value, const std::string& path,
                                  const std::string& what) {
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

// Three numbers. \throw InputError naming `what`.
inline Vec3 vectorFrom(const json& value, const std::string& path, const std::string& what) {
  if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
      !value[2].is_number())
    throw InputError(path, what + ": expected 3 numbers");
  return Vec3(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
}

}  // namespace scanplan::detail
