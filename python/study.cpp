// scanplan.study: a study (docs/study.md) run by the scanplan command, each plan in a
// process of its own as the command runs them, its table returned as Python rows.

#include "study.h"

#include <pybind11/eval.h>

namespace scanplan::python {

namespace py = pybind11;

namespace {

constexpr const char* kStudy = R"(
def study(path, out="study-out", jobs=None, dask=None, scanplan=None):
    """Plans the study file `path` (parts x scanners x specs x orientations x coverage
    targets) with the scanplan command, on this machine (`jobs` plans at a time, one per
    core by default) or on the Dask cluster at `dask` ("tcp://HOST:PORT"). Writes each plan
    under out/plans/, study.csv and study.html into `out`, reuses the plans done by an
    earlier run, and returns the table: one dict per plan, keyed by study.csv's columns. A
    plan that fails is a row with status "failed" and its error. The command is `scanplan`,
    else $SCANPLAN_CLI, else the one on the PATH."""
    import csv, os, shutil, subprocess
    exe = scanplan or os.environ.get("SCANPLAN_CLI") or shutil.which("scanplan")
    if not exe:
        raise _scanplan_error(UsageError, "scanplan", "the scanplan command is not on the PATH: "
                              "install it (cmake --install) or pass scanplan=", 1)
    argv = [exe, "-q", "study", os.fspath(path), "-o", os.fspath(out)]
    if jobs:
        argv += ["--jobs", str(int(jobs))]
    if dask:
        argv += ["--dask", str(dask)]
    done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode not in (0, 3):
        errors = [l[7:] for l in done.stdout.splitlines() if l.startswith("error: ")]
        file, _, reason = (errors[-1] if errors else done.stdout.strip()).partition(": ")
        kind = {1: UsageError, 2: InputError, 4: OutputError}.get(done.returncode, Error)
        raise _scanplan_error(kind, file, reason or file, done.returncode)
    with open(os.path.join(os.fspath(out), "study.csv"), newline="") as table:
        return list(csv.DictReader(table))


def _scanplan_error(kind, file, reason, exit_code):
    error = kind(file + ": " + reason if file else reason)
    error.file, error.reason, error.exit_code = file, reason, exit_code
    return error
)";

}  // namespace

void bindStudy(py::module_& m) { py::exec(kStudy, m.attr("__dict__")); }

}  // namespace scanplan::python
