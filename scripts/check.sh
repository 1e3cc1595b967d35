#!/usr/bin/env bash
# Installs the dependencies, builds scanplan with warnings as errors and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset ci
cmake --build --preset ci
# The tests on the real parts of ../shared/data: in CI (CI set), which has that folder
# beside the clone, and wherever it is, a file of it that a test needs and cannot find
# fails the test; on a machine without it, those tests are skipped, each saying so.
if [ -n "${CI:-}" ] || [ -d ../shared/data ]; then
  export SCANPLAN_REQUIRE_SHARED_DATA=1
else
  echo "check: ../shared/data not found: the tests on its parts are skipped" >&2
fi
ctest --preset ci -j "$(nproc)"
