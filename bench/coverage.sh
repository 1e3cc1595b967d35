#!/usr/bin/env bash
# Views and cycle time against the coverage target (docs/benchmarks.md, "Coverage
# targets"): plans PART at each share of its coverable samples and prints a table row per
# share, from plan.json: views, those registered, samples measured, cycle, the greedy
# prefix and the bound.
#   bench/coverage.sh SCANPLAN PART [SPEC|-] [--no-registration] [SHARES...]
set -euo pipefail
exe=$1 part=$2 spec=${3:--}
shift $(( $# < 3 ? $# : 3 ))
extra=()
if [ "${1:-}" = "--no-registration" ]; then extra+=(--no-registration); shift; fi
shares=("$@")
[ ${#shares[@]} -gt 0 ] || shares=(1 0.98 0.95 0.9)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| coverage | views (selected) | registered | measured | cycle s | greedy prefix | bound | planning s |"
echo "|---|---|---|---|---|---|---|---|"
for share in "${shares[@]}"; do
  args=(plan "$part" -o "$out/$share" --no-report -q --coverage "$share" "${extra[@]}")
  [ "$spec" = "-" ] || args+=(--spec "$spec")
  /usr/bin/time -f "%e" -o "$out/time" "$exe" "${args[@]}" > /dev/null
  python3 - "$out/$share/plan.json" "$share" "$(cat "$out/time")" <<'PY'
import json, sys
plan = json.load(open(sys.argv[1]))
s = plan["summary"]
coverable = s["samples"] - s["not_coverable"]
cycle = s.get("cycle", {}).get("seconds")
bound = s.get("bound", {})
registered = s.get("registrable_views")
print(f"| {float(sys.argv[2]):.2f} | {s['views']} ({bound.get('views', '-')}) | "
      f"{'-' if registered is None else registered} | {s['measured']} of {coverable} "
      f"({100 * s['measured'] / max(coverable, 1):.1f}%) | "
      f"{'-' if cycle is None else f'{cycle:.0f}'} | {bound.get('greedy_views', '-')} | "
      f"{bound.get('lower_bound', '-')} | {float(sys.argv[3]):.1f} |")
PY
done
