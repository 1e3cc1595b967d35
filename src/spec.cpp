#include <scanplan/errors.h>
#include <scanplan/spec.h>

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

namespace scanplan {

Spec defaultSpec() {
  Spec spec;
  spec.scanner = scannerPreset("generic-structured-light");
  return spec;
}

namespace {

std::vector<int> faceIds(const YAML::Node& node, const std::string& path, const std::string& key) {
  std::vector<int> ids;
  if (!node) return ids;
  if (!node.IsSequence()) throw InputError(path, key + " must be a list of face ids");
  for (const YAML::Node& item : node) {
    int id = 0;
    try {
      id = item.as<int>();
    } catch (const YAML::Exception&) {
      throw InputError(path, key + ": '" + YAML::Dump(item) + "' is not a face id");
    }
    if (id < 1) throw InputError(path, key + ": face ids start at 1, got " + std::to_string(id));
    ids.push_back(id);
  }
  return ids;
}

}  // namespace

Spec loadSpec(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "no such file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path, "not valid YAML: " + std::string(e.what()));
  }
  Spec spec = defaultSpec();
  spec.source = path;
  if (root.IsNull()) return spec;
  if (!root.IsMap())
    throw InputError(path, "a spec is a mapping of sections (scanner, part, roles, ...)");
  static const std::set<std::string> sections = {"scanner", "part",  "roles",   "gdt",
                                                 "markers", "tasks", "planner", "cell"};
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    if (!sections.count(key)) throw InputError(path, "unknown section '" + key + "'");
  }
  try {
    if (root["scanner"]) spec.scanner = loadScanner(path);
    if (const YAML::Node roles = root["roles"]) {
      if (!roles.IsMap()) throw InputError(path, "roles must be a mapping");
      spec.priority_faces = faceIds(roles["priority"], path, "roles.priority");
      spec.specular_faces = faceIds(roles["specular"], path, "roles.specular");
    }
    if (const YAML::Node cell = root["cell"]) {
      if (cell["working_plane"]) spec.working_plane = cell["working_plane"].as<bool>();
    }
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.what());
  }
  return spec;
}

}  // namespace scanplan
