#!/usr/bin/env bash
# Plans a fixed set of parts and compares the plans with a recorded set, to show that a
# refactoring leaves every plan as it was.
#
#   scripts/plan-snapshots.sh record  DIR [SCANPLAN]   plan every case into DIR
#   scripts/plan-snapshots.sh compare DIR [SCANPLAN]   plan again and compare with DIR
#
# The cases: the bundled example with its spec, the gdt and global tasks of every NIST
# model found in $SCANPLAN_SHARED_DATA/nist (default ../shared/data/nist), and on NIST FTC 11
# a plan in a robot cell, one over every rest orientation and one of the surface task. Plans are
# compared as JSON with every "seconds" and "stage_seconds" field and the part's path removed
# (it is relative to where the plan is written): every field of
# the recorded plan must be there and equal; fields the new plan adds are listed. The
# numbers of ICP checks are compared to 1e-9 relative: Open3D's parallel reductions make
# them differ in the last digits between two runs of one binary. SCANPLAN
# defaults to build/release/apps/scanplan/scanplan. Two plans run at a time.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-}
dir=${2:-}
scanplan=$(realpath "${3:-build/release/apps/scanplan/scanplan}")
if [[ ! "$mode" =~ ^(record|compare)$ || -z "$dir" ]]; then
  echo "usage: $0 record|compare DIR [SCANPLAN]" >&2
  exit 1
fi
[ -x "$scanplan" ] || { echo "error: $scanplan: no scanplan binary" >&2; exit 1; }
nist=${SCANPLAN_SHARED_DATA:-../shared/data}/nist

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'tasks:\n  - {type: gdt}\ngdt: from-file\n' >"$work/gdt.yaml"
printf 'tasks:\n  - {type: global}\n' >"$work/global.yaml"
printf 'cell:\n  robot: {preset: abb-irb4600-60-205, base: {position: [-1000, 0, 0]}}\n  mount: {position: [0, 0, 150]}\n' >"$work/cell.yaml"
printf 'part: {rest: all}\nregistration: {required: false}\ntasks:\n  - {type: gdt}\ngdt: from-file\n' >"$work/rest-all.yaml"
printf 'registration: {required: false}\ntasks:\n  - {type: surface, faces: [1, 2, 3, 4, 5, 6, 7, 8]}\n' >"$work/surface.yaml"

# One case per line: name, part, spec.
{
  echo "example examples/parts/nist_ctc_01_asme1_ap242-e1.stp examples/specs/ctc01.yaml"
  for part in "$nist"/*.stp; do
    [ -e "$part" ] || continue
    name=$(basename "$part" .stp)
    echo "$name-gdt $part $work/gdt.yaml"
    echo "$name-global $part $work/global.yaml"
  done
  ftc11=$nist/nist_ftc_11_asme1_ap242-e1.stp
  if [ -e "$ftc11" ]; then
    for spec in cell rest-all surface; do echo "ftc11-$spec $ftc11 $work/$spec.yaml"; done
  fi
} >"$work/cases"

out=$dir
[ "$mode" = compare ] && out=$work/new
mkdir -p "$out"
export scanplan out
xargs -P 2 -L 1 bash -c '
  "$scanplan" --quiet plan "$1" --spec "$2" -o "$out/$0" --no-report >"$out/$0.log" 2>&1 ||
    echo "plan failed: $0 (see $out/$0.log)" >&2
  echo "planned $0"' <"$work/cases"
[ "$mode" = record ] && exit 0

python3 - "$dir" "$out" "$work/cases" <<'EOF'
import json, sys
old, new, cases = sys.argv[1:4]
def load(path):
    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k not in ("seconds", "stage_seconds")}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x
    try:
        with open(path) as f:
            plan = strip(json.load(f))
        # Where the part lies from the plan's folder depends on where the plan is written.
        for key in ("file", "absolute_file"):
            plan.get("part", {}).pop(key, None)
        return plan
    except OSError:
        return None
added = set()
def first_difference(a, b, where="plan"):
    if type(a) != type(b) and not {type(a), type(b)} <= {int, float}:
        return where
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in b:
                return f"{where}.{k} (missing)"
            if k not in a:
                added.add(f"{where}.{k}")
                continue
            d = first_difference(a[k], b[k], f"{where}.{k}")
            if d:
                return d
    elif isinstance(a, list):
        if len(a) != len(b):
            return f"{where} (length {len(a)} against {len(b)})"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{where}[{i}]")
            if d:
                return d
    elif isinstance(a, float) and ".icp." in where:
        if abs(a - b) > 1e-9 * max(1.0, abs(a), abs(b)):
            return where
    elif a != b:
        return where
    return None
failed = 0
for line in open(cases):
    name = line.split()[0]
    a, b = load(f"{old}/{name}/plan.json"), load(f"{new}/{name}/plan.json")
    if a is None or b is None:
        print(f"{name:40} missing plan"); failed += 1; continue
    d = first_difference(a, b)
    print(f"{name:40} {'identical' if d is None else 'differs at ' + d}")
    failed += d is not None
if added:
    print("fields the new plans add:", ", ".join(sorted(added)[:10]))
sys.exit(1 if failed else 0)
EOF
