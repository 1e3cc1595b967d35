#!/usr/bin/env bash
# Registration by reference points against registration by marker pairs
# (docs/benchmarks.md, "Reference points"): plans each PART on a marker plate (markers
# every 40 mm around it, `markers: {grid: 40, on: plate}`) by `markers`, by
# `reference_points`, by `reference_points` with `--place-markers` and without
# registration, and prints a table row per part from plan.json: views and views registered
# under each, and the markers placed.
#   bench/reference_points.sh SCANPLAN PART...
set -euo pipefail
exe=$1
shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| part | markers: views | registered | reference_points: views | registered | placed: views | registered | markers placed | no registration: views | planning s (markers, reference_points, placed) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for part in "$@"; do
  name=$(basename "$part")
  rm -rf "$out/markers" "$out/reference_points" "$out/placed" "$out/none"
  for method in markers reference_points; do
    printf 'markers: {grid: 40, on: plate}\nregistration: {method: %s}\n' "$method" > "$out/$method.yaml"
    /usr/bin/time -f "%e" -o "$out/$method.time" \
      "$exe" -q plan "$part" --spec "$out/$method.yaml" -o "$out/$method" --no-report > /dev/null || true
  done
  /usr/bin/time -f "%e" -o "$out/placed.time" "$exe" -q plan "$part" --spec "$out/reference_points.yaml" \
    -o "$out/placed" --no-report --place-markers > /dev/null || true
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
placed_csv = os.path.join(out, "placed", "proposed-markers.csv")
placed = sum(1 for _ in open(placed_csv)) - 1 if os.path.exists(placed_csv) else 0
row = [name] + cells("markers") + cells("reference_points") + cells("placed") + [str(placed)]
row += [str(none["views"]) if none else "failed"]
row.append(f"{seconds('markers')}, {seconds('reference_points')}, {seconds('placed')}")
print("| " + " | ".join(row) + " |")
PY
done
