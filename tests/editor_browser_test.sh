#!/usr/bin/env bash
# The spec editor in headless Chromium on the bundled example (NIST CTC 01):
# web/test/editor_test.mjs drives it as an engineer would and plans what it downloads; then
# a spec loaded into the editor and downloaded unchanged reads as the same spec
# (tests/spec_equivalent.py). Last, the page's spec writer alone on a cube with named faces
# (web/test/spec_yaml_test.mjs).
#   tests/editor_browser_test.sh SCANPLAN_EXE PART [SCREENSHOT.png]
set -euo pipefail
scanplan=$1
part=$2
screenshot=${3:-}
here=$(dirname "$0")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
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
node "$here/../web/test/editor_test.mjs" "$scanplan" "$part" "$out" $screenshot
python3 "$here/spec_equivalent.py" "$out/given.yaml" "$out/roundtrip.yaml"
mkdir "$out/writer"
node "$here/../web/test/spec_yaml_test.mjs" "$scanplan" "$out/writer"
