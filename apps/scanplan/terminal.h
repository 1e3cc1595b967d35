#pragma once
// Progress and messages on the user's terminal.

#include "commands.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/progress.h>

#include <string>
#include <vector>

namespace scanplan::cli {

// A Progress that redraws one status line on stderr when stderr is a terminal, and
// stays silent otherwise or under --quiet. Under --verbose, it also writes each stage's
// time on stderr when the stage ends (a stage ends when the next begins).
Progress terminalProgress(const GlobalOptions& global);

// Ends the status line, if one is shown, and under --verbose the stage under way.
void clearProgress();

// Writes each warning on stderr as "warning: <file>: <warning>" (an empty `file`: none),
// after the status line, even under --quiet.
void printWarnings(const std::string& file, const std::vector<std::string>& warnings);

// importPart(), with the part's import warnings written by printWarnings().
Part importWithWarnings(const std::string& path, const ImportOptions& options,
                        const Progress& progress);

}  // namespace scanplan::cli
