#pragma once
// Progress and messages on the user's terminal.

#include "commands.h"

#include <scanplan/core/progress.h>

#include <string>

namespace scanplan::cli {

// A Progress that redraws one status line on stderr when stderr is a terminal, and
// stays silent otherwise or under --quiet. Under --verbose, it also writes each stage's
// time on stderr when the stage ends (a stage ends when the next begins).
Progress terminalProgress(const GlobalOptions& global);

// Ends the status line, if one is shown, and under --verbose the stage under way.
void clearProgress();

}  // namespace scanplan::cli
