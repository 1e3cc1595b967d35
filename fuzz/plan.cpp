// Fuzzes the plan reader (plan.json), and the spec a plan holds as the commands read it.
#include "input_file.h"

#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scanplan::fuzz::readOrRefuse(data, size, ".json", [](const std::string& path) {
    scanplan::planSpec(scanplan::readPlan(path), path);
  });
}
