#include "files.h"

#include <scanplan/core/errors.h>

#include <filesystem>

namespace scanplan::cli {

void refuseInputAsOutput(const std::string& out, std::initializer_list<std::string> inputs) {
  std::error_code ec;
  for (const std::string& in : inputs)
    if (!in.empty() && std::filesystem::equivalent(in, out, ec))
      throw OutputError(out, "is an input of this command (" + in + "): choose another output");
}

}  // namespace scanplan::cli
