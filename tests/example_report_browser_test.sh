#!/usr/bin/env bash
# The HTML report of the bundled example's plan (153 views, made once for the test run by
# PlanBundledExample) opened in headless Chromium: web/test/report_test.mjs checks that a
# page of that many views draws and answers, as it does for a small plan.
#   tests/example_report_browser_test.sh SCANPLAN_EXE EXAMPLES EXAMPLE_PLAN_DIR
set -euo pipefail
scanplan=$1
examples=$2
plan=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cp "$plan/plan.json" "$out/plan.json"
"$scanplan" report "$out/plan.json" "$examples/parts/nist_ctc_01_asme1_ap242-e1.stp" \
  --spec "$examples/specs/ctc01.yaml" -q > /dev/null
node "$(dirname "$0")/../web/test/report_test.mjs" "$out/report.html" "$out/plan.json"
