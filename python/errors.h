#pragma once
// The library's errors as Python exceptions: scanplan.Error and, below it, UsageError,
// InputError, PlanningError, OutputError and LibraryError, each with `file`, `reason`
// and `exit_code` (the command line's exit code for the same failure).

#include <pybind11/pybind11.h>

namespace scanplan::python {

void bindErrors(pybind11::module_& m);

}  // namespace scanplan::python
