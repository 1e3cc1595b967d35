#!/usr/bin/env bash
# Installs the dependencies, builds scanplan and runs it on the bundled example part
# (NIST CTC 01, STEP AP242 with semantic GD&T).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release
cmake --build --preset release --target scanplan_cli
build/release/apps/scanplan/scanplan info examples/parts/nist_ctc_01_asme1_ap242-e1.stp
