#include "files.h"

#include <scanplan/core/errors.h>

#include <filesystem>

namespace scanplan::cli {

std::vector<std::string> commandInputs(std::vector<std::string> inputs, const Spec& spec) {
  const std::vector<std::string> named = specFiles(spec);
  inputs.insert(inputs.end(), named.begin(), named.end());
  return inputs;
}

void refuseInputAsOutput(const std::string& out, const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const std::string& in : inputs)
    if (!in.empty() && std::filesystem::equivalent(in, out, ec))
      throw OutputError(out, "is an input of this command (" + in + "): choose another output");
}

}  // namespace scanplan::cli
