#!/bin/sh
# Plans the bundled example with its spec once for the test run:
#   plan_example.sh SCANPLAN EXAMPLES OUTDIR
# writes OUTDIR/plan.json and the printed summary OUTDIR/summary.txt.
set -e
rm -rf "$3"
mkdir -p "$3"
"$1" -q plan "$2/parts/nist_ctc_01_asme1_ap242-e1.stp" --spec "$2/specs/ctc01.yaml" \
  -o "$3" --no-report >"$3/summary.txt"
