// Fuzzes the plan reader (plan.json).
#include "input_file.h"

#include <scanplan/io/plan_json.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scanplan::fuzz::readOrRefuse(data, size, ".json",
                                      [](const std::string& path) { scanplan::readPlan(path); });
}
