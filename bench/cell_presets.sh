#!/usr/bin/env bash
# Every robot preset on PART (docs/cell.md, "The presets on two parts"): the part on a
# rotary table at the origin, the robot's base 0.75 of its reach from the table's axis
# (600 mm at least), the scanner 150 mm out on the flange. Plans each cell, exports the
# program in its maker's format and prints one row per preset: views, views the cell
# cannot reach, moves not cleared, the program's joint and table travel and the cycle time
# (docs/cycle.md), and whether the program was written.
#   bench/cell_presets.sh SCANPLAN PART
set -euo pipefail
exe=$1 part=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A reach=([kuka-kr6-r700-sixx]=706 [kuka-kr10-r1100-2]=1101 [kuka-kr16-r1610-2]=1612
                  [abb-irb2400-10]=1550 [abb-irb4600-60-205]=2050 [fanuc-m20id-25]=1831
                  [fanuc-lrmate200id]=717 [ur5e]=850 [ur10e]=1300 [ur16e]=900)
declare -A format=([kuka]=krl [abb]=rapid [fanuc]=fanuc [ur]=urscript)
declare -A extension=([krl]=src [rapid]=mod [fanuc]=ls [urscript]=script)
echo "| preset | base from the table's axis, mm | views | not reached | moves not cleared | joint and table travel, s | cycle, s | program |"
echo "|---|---|---|---|---|---|---|---|"
for preset in kuka-kr6-r700-sixx kuka-kr10-r1100-2 kuka-kr16-r1610-2 abb-irb2400-10 \
              abb-irb4600-60-205 fanuc-m20id-25 fanuc-lrmate200id ur5e ur10e ur16e; do
  distance=$(( reach[$preset] * 3 / 4 ))
  (( distance < 600 )) && distance=600
  maker=${preset%%-*}
  [[ $maker == ur* ]] && maker=ur
  signals=""
  [ "$maker" = ur ] && signals="  signals: {table: {angle: 0, move: 2, ready: 2}}"
  cat > "$out/spec.yaml" <<EOF
cell:
  robot: {preset: $preset, base: {position: [-$distance, 0, 0]}}
  mount: {position: [0, 0, 150]}
  table: {origin: [0, 0, 0], axis: [0, 0, 1], range: [-180, 180], step: 15}
$signals
EOF
  rm -rf "$out/plan"
  "$exe" plan "$part" --spec "$out/spec.yaml" -o "$out/plan" --no-report -q > /dev/null
  fmt=${format[$maker]}
  written=no
  "$exe" export "$out/plan/plan.json" --format "$fmt" -o "$out/cell.${extension[$fmt]}" -q \
    > /dev/null 2>&1 && written=$fmt
  python3 - "$out/plan/plan.json" "$preset" "$distance" "$written" <<'PY'
import json, sys
plan = json.load(open(sys.argv[1]))
s = plan["summary"]
robot = s.get("robot", {})
cycle = s.get("cycle", {})
print(f"| `{sys.argv[2]}` | {sys.argv[3]} | {s['views']} | {robot.get('unreached_views', 0)} "
      f"| {len(robot.get('uncleared_moves', []))} | {robot.get('travel_seconds', 0):.1f} "
      f"| {cycle.get('seconds', 0):.1f} | {sys.argv[4]} |")
PY
done
