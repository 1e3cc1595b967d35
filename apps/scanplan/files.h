#pragma once
// Checks on the files a command is given.

#include <initializer_list>
#include <string>

namespace scanplan::cli {

// \throw OutputError naming `out` when it is one of the command's `inputs` (those given;
// empty ones are skipped).
void refuseInputAsOutput(const std::string& out, std::initializer_list<std::string> inputs);

}  // namespace scanplan::cli
