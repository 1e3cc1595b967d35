#!/usr/bin/env bash
# The HTML report of a small plan (NIST FTC 11, its GD&T and whole shape) opened in
# headless Chromium: web/test/report_test.mjs checks it.
#   tests/report_browser_test.sh SCANPLAN_EXE PART
set -euo pipefail
scanplan=$1
part=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf 'gdt: from-file\ntasks:\n  - {type: gdt}\n  - {type: global}\n' > "$out/spec.yaml"
"$scanplan" plan "$part" --spec "$out/spec.yaml" -o "$out" -q > /dev/null
# The report again, with a short virtual inspection beside the plan.
"$scanplan" inspect "$out/plan.json" "$part" --spec "$out/spec.yaml" --runs 2 -q > /dev/null
"$scanplan" report "$out/plan.json" "$part" --spec "$out/spec.yaml" -q > /dev/null
node "$(dirname "$0")/../web/test/report_test.mjs" "$out/report.html" "$out/plan.json"
