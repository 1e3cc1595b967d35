// Fuzzes the CAD readers (IGES, BREP, STEP), which run OCCT's parsers in the isolated
// reader: the first byte picks the format. A crash of OCCT must come back as an error.
#include "input_file.h"

#include <scanplan/cad/import.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".igs", ".brep", ".step"};
  return scanplan::fuzz::readOrRefuse(data + 1, size - 1, kExtensions[data[0] % 3],
                                      [](const std::string& path) { scanplan::importPart(path); });
}
