// Fuzzes the inspection spec reader (YAML).
#include "input_file.h"

#include <scanplan/io/spec_yaml.h>
#include <scanplan/spec/spec.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scanplan::fuzz::readOrRefuse(data, size, ".yaml",
                                      [](const std::string& path) { scanplan::loadSpec(path); });
}
