#pragma once
// scanplan.study, run by the scanplan command (docs/study.md).

#include <pybind11/pybind11.h>

namespace scanplan::python {

// Adds `study` to the module: Python code that runs `scanplan study` and reads its table.
void bindStudy(pybind11::module_& m);

}  // namespace scanplan::python
