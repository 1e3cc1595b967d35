// Fuzzes the points and markers CSV reader.
#include "input_file.h"

#include <scanplan/io/points_csv.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scanplan::fuzz::readOrRefuse(data, size, ".csv", [](const std::string& path) {
    scanplan::readPointsCsv(path);
  });
}
