#!/usr/bin/env bash
# The spec editor in headless Chromium on the bundled example (NIST CTC 01), driven by
# web/test/editor_test.mjs as an engineer would.
#   tests/editor_browser_test.sh new SCANPLAN_EXE PART [SCREENSHOT.png]
#     a new spec: faces, a characteristic and points picked, and what is downloaded planned;
#   tests/editor_browser_test.sh given SCANPLAN_EXE PART
#     a spec loaded and downloaded unchanged reads as the same spec
#     (tests/spec_equivalent.py), then edited; last, the page's spec writer alone on a cube
#     with named faces (web/test/spec_yaml_test.mjs).
set -euo pipefail
mode=$1
scanplan=$2
part=$3
screenshot=${4:-}
here=$(dirname "$0")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ "$mode" = new ]; then
  node "$here/../web/test/editor_test.mjs" new "$scanplan" "$part" "$out" $screenshot
  exit
fi
# Every section the editor shows, and some it only keeps; faces by id, sorted.
cat > "$out/given.yaml" <<'YAML'
scanner: laser-line
part:
  rest: auto
gdt: from-file
roles:
  priority: [98]
  fixture: [1, 2]
  specular: [46]
markers: {grid: 40, margin: 60, on: both}
fixtures:
  - file: clamp.obj
    placement: {position: [0, 0, 5], rotation: [0, 0, 90]}
    frame: world
registration:
  method: geometry
  max_condition: 30
planner:
  seed: 7
  tilt: [25, 45]
tasks:
  - {type: gdt}
  - type: trim
    faces: [7, 9]
  - {type: global}
  - {type: points, file: given-points.csv}
YAML
printf 'x,y,z,nx,ny,nz\n-358.021981,166.590179,0,0,0,1\n-252.101466,189.343308,-33.333329\n' \
  > "$out/given-points.csv"
# The clamp: a 20 mm cube.
printf 'v 0 0 0\nv 20 0 0\nv 20 20 0\nv 0 20 0\nv 0 0 20\nv 20 0 20\nv 20 20 20\nv 0 20 20\n%s\n' \
  'f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8' > "$out/clamp.obj"
node "$here/../web/test/editor_test.mjs" given "$scanplan" "$part" "$out"
python3 "$here/spec_equivalent.py" "$out/given.yaml" "$out/roundtrip.yaml"
mkdir "$out/writer"
node "$here/../web/test/spec_yaml_test.mjs" "$scanplan" "$out/writer"
