#!/bin/sh
# The Python module as a user installs it:
#   python_install_test.sh BUILD_DIR PYTHON PART
# makes a virtual environment of PYTHON (with the system's packages, for numpy), installs
# BUILD_DIR into it with cmake --install, and plans PART with the environment's Python from
# outside the source and build trees, without PYTHONPATH.
set -eu
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset PYTHONPATH SCANPLAN_DATA
"$2" -m venv --system-site-packages --without-pip "$work/env"
cmake --install "$1" --prefix "$work/env" >/dev/null
cp "$3" "$work/part.stp"
cd "$work"
"$work/env/bin/python3" - <<'PY'
import os
import scanplan

where = os.path.realpath(scanplan.__file__)
assert where.startswith(os.path.realpath("env")), f"scanplan imported from {where}"
plan = scanplan.plan(scanplan.import_part("part.stp"), registration=False)
views, share = len(plan.view_ids), plan.measured_share
assert views > 0 and share > 0.5, (views, share)
scanplan.write_plan(plan, "plan.json")
print(f"{views} views, {share:.1%} measured, from {where}")
PY
test -s plan.json
