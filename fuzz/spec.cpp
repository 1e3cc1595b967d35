// Fuzzes the inspection spec reader (YAML).
#include "input_file.h"

#include <scanplan/spec.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scanplan::fuzz::readOrRefuse(data, size, ".yaml",
                                      [](const std::string& path) { scanplan::loadSpec(path); });
}
