// The check every input file passes before it is read.

#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>

#include <filesystem>
#include <fstream>

namespace scanplan {

void requireInputFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(path, "no such file");
  if (fs::is_directory(status)) throw InputError(path, "not a regular file (a directory)");
  if (!fs::is_regular_file(status)) throw InputError(path, "not a regular file");
  if (!std::ifstream(path).good()) throw InputError(path, "cannot be opened for reading");
}

}  // namespace scanplan
