#!/usr/bin/env bash
# Installs the dependencies, builds scanplan with warnings as errors and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset ci
cmake --build --preset ci
# The tests on the real parts of ../shared/data: where that folder is, a file of it that a
# test needs and cannot find fails the test; where it is not, those tests are skipped.
if [ -d ../shared/data ]; then
  export SCANPLAN_REQUIRE_SHARED_DATA=1
else
  echo "check: ../shared/data not found: the tests on its parts are skipped" >&2
fi
ctest --preset ci -j "$(nproc)"
