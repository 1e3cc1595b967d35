#pragma once
// The files of `scanplan inspect`: the deviations declared on the simulated part (YAML)
// and the inspection's results (JSON), docs/capability.md, "Virtual inspection".

#include <scanplan/plan/inspection.h>
#include <scanplan/plan/plan.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace scanplan {

// `deviations:` a list of {faces: [ids], and one of offset: mm, bow: mm, move: [x, y, z],
// diameter: mm}. \throw InputError naming `path` and the entry at fault.
std::vector<Deviation> loadDeviations(const std::string& path);
// The same read from `text`, errors naming `source`.
std::vector<Deviation> deviationsFromText(const std::string& text, const std::string& source);

// The inspection with each characteristic's kind, width and datums from `plan`.
nlohmann::json inspectionJson(const Inspection& inspection, const Plan& plan);
// \throw OutputError naming `path`.
void writeInspection(const Inspection& inspection, const Plan& plan, const std::string& path);
// An inspection written by writeInspection, its characteristics those of `plan`.
// \throw InputError naming `path` and the field at fault.
Inspection readInspection(const std::string& path, const Plan& plan);

}  // namespace scanplan
