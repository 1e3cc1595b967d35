#!/usr/bin/env bash
# Plans aimed at samples and at characteristics (docs/benchmarks.md, "Aim"): plans PART with
# SPEC under each planner.aim and prints a table row per aim from plan.json: views, cycle
# time, characteristics capable of those with a tolerance, the limits of those left short,
# and the planning time. With --inspected, then a row per characteristic of the plan aimed
# at characteristics: its predicted U beside the virtual inspection's U and bias, from the
# plan's own inspection (20 runs), or from `scanplan inspect` with RUNS runs when given, its
# points SPACING mm apart at the standoff when given (`scanplan inspect --spacing`; default a
# hundredth of the field). The inspected U + |bias| is itself uncertain, by about 16 % over
# 20 runs: the ratio's interval at 95 % comes from the inspection's stated precision. With
# RUNS, the last column is the predicted U over the error 95 % of the runs stay under
# (|measured - true|), which is how the capability model defines its U.
#   bench/aim.sh SCANPLAN PART [SPEC|-] [--inspected [RUNS [SPACING]]]
set -euo pipefail
exe=$1 part=$2 spec=${3:--} inspected=${4:-} runs=${5:-} spacing=${6:-}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| aim | views | cycle s | capable | beyond the views | planning s |"
echo "|---|---|---|---|---|---|"
for aim in samples characteristics; do
  args=(plan "$part" -o "$out/$aim" --no-report -q --aim "$aim")
  [ "$spec" = "-" ] || args+=(--spec "$spec")
  /usr/bin/time -f "%e" -o "$out/time" "$exe" "${args[@]}" > /dev/null
  python3 - "$out/$aim/plan.json" "$aim" "$(cat "$out/time")" <<'PY'
import collections, json, sys
plan = json.load(open(sys.argv[1]))
s = plan["summary"]
judged = [c["capability"] for c in plan.get("characteristics", []) if c.get("capability")]
toleranced = [k for k in judged if k["verdict"] != "untoleranced"]
capable = sum(k["verdict"] == "capable" for k in toleranced)
limits = collections.Counter(k.get("limit", "none") for k in toleranced if k["verdict"] != "capable")
cycle = s.get("cycle", {}).get("seconds")
print(f"| {sys.argv[2]} | {s['views']} | {'-' if cycle is None else f'{cycle:.0f}'} | "
      f"{capable} of {len(toleranced)} | "
      f"{', '.join(f'{n} {l}' for l, n in sorted(limits.items())) or '-'} | {float(sys.argv[3]):.1f} |")
PY
done
[ "$inspected" = "--inspected" ] || exit 0
echo
echo "| id | kind | width | predicted U | inspected U | inspected bias | ± at 95 % | predicted / (|bias| + U) | predicted / 95 % of the errors |"
echo "|---|---|---|---|---|---|---|---|---|"
inspection=-
if [ -n "$runs" ]; then
  args=(inspect "$out/characteristics/plan.json" "$part" --runs "$runs" -q
        -o "$out/inspection.json")
  [ "$spec" = "-" ] || args+=(--spec "$spec")
  [ -z "$spacing" ] || args+=(--spacing "$spacing")
  "$exe" "${args[@]}" > /dev/null
  inspection=$out/inspection.json
fi
python3 - "$out/characteristics/plan.json" "$inspection" <<'PY'
import json, sys
plan = json.load(open(sys.argv[1]))
# (U, bias, precision of U + |bias|, the error 95 % of the runs stay under) per
# characteristic: the plan's own inspection's (without the last), or the given
# inspection's.
inspected = {c["id"]: (c["uncertainty"], c["bias"], c["precision"], c["error_95"])
             for c in (json.load(open(sys.argv[2]))["characteristics"] if sys.argv[2] != "-" else [])
             if c.get("evaluated")}
for c in plan.get("characteristics", []):
    k = c.get("capability") or {}
    if sys.argv[2] == "-" and k.get("inspected_uncertainty") is not None:
        inspected[c["id"]] = (k["inspected_uncertainty"], k["inspected_bias"],
                              k.get("inspected_precision") or 0, 0)
    if k.get("verdict") == "untoleranced" or c["id"] not in inspected:
        continue
    u, bias, precision, q95 = inspected[c["id"]]
    width = c["limits"][1] - c["limits"][0]
    seen = abs(bias) + u
    ratio = (lambda x: f"{k['uncertainty'] / x:.2f}" if x > 0 else "-")
    print(f"| {c['id']} | {c['kind']} | {width:g} | {k['uncertainty']:.4f} | "
          f"{u:.4f} | {bias:.4f} | {precision:.4f} | {ratio(seen)} "
          f"({ratio(seen + precision)} to {ratio(seen - precision)}) | {ratio(q95)} |")
PY
