#!/usr/bin/env bash
# Installs the dependencies, builds scanplan, installs it into /usr/local (the command,
# the library and the Python module) and runs it on the bundled example part (NIST CTC 01,
# STEP AP242 with semantic GD&T): what it reads, then the plan of its GD&T faces and of
# its whole shape, written to example-out/plan.json with its 3D report
# example-out/report.html and a picture example-out/plan.png.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release
cmake --build --preset release --target scanplan_cli scanplan_python
cmake --install build/release --prefix /usr/local
scanplan=/usr/local/bin/scanplan
"$scanplan" info examples/parts/nist_ctc_01_asme1_ap242-e1.stp
"$scanplan" plan examples/parts/nist_ctc_01_asme1_ap242-e1.stp \
  --spec examples/specs/ctc01.yaml -o example-out --png
echo "Open example-out/report.html in a browser to see the plan."
echo "scanplan is installed in /usr/local/bin; 'scanplan --help' lists its commands."
