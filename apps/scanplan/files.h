#pragma once
// Checks on the files a command is given.

#include <scanplan/spec/spec.h>

#include <string>
#include <vector>

namespace scanplan::cli {

// The files a command reads: `inputs`, and those `spec` names, itself included
// (specFiles()). Empty names are skipped.
std::vector<std::string> commandInputs(std::vector<std::string> inputs, const Spec& spec);

// \throw OutputError naming `out` when it is one of `inputs`.
void refuseInputAsOutput(const std::string& out, const std::vector<std::string>& inputs);

}  // namespace scanplan::cli
