// Fuzzes the mesh readers (STL, OFF, OBJ, PLY): the first byte picks the format.
#include "input_file.h"

#include <scanplan/cad/import.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".stl", ".off", ".obj", ".ply"};
  return scanplan::fuzz::readOrRefuse(data + 1, size - 1, kExtensions[data[0] % 4],
                                      [](const std::string& path) { scanplan::importPart(path); });
}
