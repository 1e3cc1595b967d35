#pragma once
// The inspection spec (DESIGN.md §6), YAML in millimetres and degrees. Every field has a
// default, so an empty spec means the default scanner and no special roles.

#include <scanplan/sensor.h>

#include <string>
#include <vector>

namespace scanplan {

struct Spec {
  std::string source;               // the file it was read from, "" for defaults
  Scanner scanner;                  // `scanner:` preset name or mapping
  std::vector<int> priority_faces;  // roles.priority (face ids)
  std::vector<int> specular_faces;  // roles.specular (face ids)
  bool working_plane = true;        // cell.working_plane: the plane z = 0 occludes
};

// The default spec: the generic structured-light scanner, no roles.
Spec defaultSpec();

// Reads and validates a spec. Face ids are checked against a part later, by the stage
// that uses them. \throw InputError naming the file and the key that is wrong.
Spec loadSpec(const std::string& path);

}  // namespace scanplan
