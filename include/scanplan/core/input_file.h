#pragma once
// The check every input file passes before it is read.

#include <string>

namespace scanplan {

// \throw InputError naming `path` unless it is a regular file (or a link to one) that can
// be opened for reading: "no such file", "not a regular file (a directory)", ...
void requireInputFile(const std::string& path);

}  // namespace scanplan
