#!/usr/bin/env bash
# Registration by reference points against registration by marker pairs
# (docs/benchmarks.md, "Reference points"): plans each PART on a marker plate (markers
# every 40 mm around it, `markers: {grid: 40, on: plate}`) by `markers`, by
# `reference_points` and without registration, and prints a table row per part from
# plan.json: views and views registered under each.
#   bench/reference_points.sh SCANPLAN PART...
set -euo pipefail
exe=$1
shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| part | markers: views | registered | reference_points: views | registered | no registration: views | planning s (markers, reference_points) |"
echo "|---|---|---|---|---|---|---|"
for part in "$@"; do
  name=$(basename "$part")
  for method in markers reference_points; do
    printf 'markers: {grid: 40, on: plate}\nregistration: {method: %s}\n' "$method" > "$out/$method.yaml"
    /usr/bin/time -f "%e" -o "$out/$method.time" \
      "$exe" -q plan "$part" --spec "$out/$method.yaml" -o "$out/$method" --no-report > /dev/null || true
  done
  "$exe" -q plan "$part" -o "$out/none" --no-report --no-registration > /dev/null || true
  python3 - "$name" "$out" <<'PY'
import json, os, sys
name, out = sys.argv[1:3]
def summary(run):
    path = os.path.join(out, run, "plan.json")
    return json.load(open(path))["summary"] if os.path.exists(path) else None
def cells(run):
    s = summary(run)
    if s is None:
        return ["failed", "-"]
    return [str(s["views"]), f"{s['registrable_views']} ({100 * s['registrable_views'] / max(s['views'], 1):.0f}%)"]
def seconds(run):
    return open(os.path.join(out, run + ".time")).read().strip().splitlines()[-1]
none = summary("none")
row = [name] + cells("markers") + cells("reference_points") + [str(none["views"]) if none else "failed"]
row.append(f"{seconds('markers')}, {seconds('reference_points')}")
print("| " + " | ".join(row) + " |")
PY
done
