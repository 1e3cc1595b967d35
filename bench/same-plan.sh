#!/usr/bin/env bash
# Whether a plan is the same on one thread, on all, and with another process keeping a core
# busy (docs/benchmarks.md, "The same plan on every machine"): plans PART three times and
# compares the plan.json files, times aside. Prints one row per run and exits 1 when any
# plan differs from the first.
#   bench/same-plan.sh SCANPLAN PART [SPEC|-] [PLAN OPTIONS...]
set -euo pipefail
exe=$1 part=$2 spec=${3:--}
shift $(( $# < 3 ? $# : 3 ))
out=$(mktemp -d)
busy=
trap '[ -z "$busy" ] || kill "$busy" 2>/dev/null; rm -rf "$out"' EXIT
args=(plan "$part" --no-report -q "$@")
[ "$spec" = "-" ] || args+=(--spec "$spec")
run() {  # name, then options before the subcommand
  local name=$1
  shift
  /usr/bin/time -f "%e %M" -o "$out/$name.time" "$exe" "$@" "${args[@]}" -o "$out/$name" > /dev/null
}
run one-thread -j 1
run all-threads
# A core kept busy by another process while the plan runs.
(while :; do :; done) &
busy=$!
run loaded
kill "$busy"
busy=
python3 - "$out" <<'PY'
import json, sys

def plan(name):
    def strip(o):
        if isinstance(o, dict):
            return {k: strip(v) for k, v in o.items() if k not in ("seconds", "stage_seconds")}
        if isinstance(o, list):
            return [strip(x) for x in o]
        return o
    return strip(json.load(open(f"{sys.argv[1]}/{name}/plan.json")))

names = ["one-thread", "all-threads", "loaded"]
first = plan(names[0])
same = True
print("| run | wall s | peak MB | views | plan as on one thread |")
print("|---|---|---|---|---|")
for name in names:
    wall, kb = open(f"{sys.argv[1]}/{name}.time").read().split()
    p = plan(name)
    same = same and p == first
    print(f"| {name} | {float(wall):.1f} | {int(kb) / 1024:.0f} | {p['summary']['views']} | "
          f"{'yes' if p == first else 'no'} |")
sys.exit(0 if same else 1)
PY
