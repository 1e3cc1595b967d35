#pragma once
// Progress and messages on the user's terminal.

#include <scanplan/progress.h>

#include <string>

namespace scanplan::cli {

// A Progress that redraws one status line on stderr when stderr is a terminal, and
// stays silent otherwise or when `quiet`.
Progress terminalProgress(bool quiet);

// Ends the status line, if one is shown.
void clearProgress();

}  // namespace scanplan::cli
