#include "errors.h"

#include <scanplan/core/errors.h>

#include <exception>

namespace scanplan::python {
namespace {

namespace py = pybind11;

// The exception classes, made once with the module and kept for the process.
struct Classes {
  PyObject* error = nullptr;
  PyObject* usage = nullptr;
  PyObject* input = nullptr;
  PyObject* planning = nullptr;
  PyObject* output = nullptr;
  PyObject* library = nullptr;
};
Classes classes;

PyObject* classOf(const Error& e) {
  if (dynamic_cast<const UsageError*>(&e)) return classes.usage;
  if (dynamic_cast<const InputError*>(&e)) return classes.input;
  if (dynamic_cast<const PlanningError*>(&e)) return classes.planning;
  if (dynamic_cast<const OutputError*>(&e)) return classes.output;
  if (dynamic_cast<const LibraryError*>(&e)) return classes.library;
  return classes.error;
}

void raise(const Error& e) {
  PyObject* type = classOf(e);
  py::object error = py::reinterpret_borrow<py::object>(type)(e.what());
  error.attr("file") = e.file();
  error.attr("reason") = e.reason();
  error.attr("exit_code") = static_cast<int>(e.exitCode());
  PyErr_SetObject(type, error.ptr());
}

PyObject* newClass(py::module_& m, const char* name, PyObject* base, const char* doc) {
  const std::string qualified = std::string("scanplan.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::reinterpret_borrow<py::object>(type));
  return type;  // the new reference is kept for the process
}

}  // namespace

void bindErrors(py::module_& m) {
  classes.error = newClass(m, "Error", PyExc_Exception,
                           "A scanplan error: `file` names the input or output, `reason` says "
                           "what is wrong, `exit_code` is the command line's");
  classes.usage = newClass(m, "UsageError", classes.error, "A request that does not fit");
  classes.input = newClass(m, "InputError", classes.error, "An unreadable or invalid input");
  classes.planning = newClass(m, "PlanningError", classes.error, "Planning failed");
  classes.output = newClass(m, "OutputError", classes.error, "An output could not be written");
  classes.library = newClass(m, "LibraryError", classes.error, "A third-party library failed");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      raise(e);
    }
  });
}

}  // namespace scanplan::python
