#!/bin/sh
# A study on a Dask cluster, as a planning department runs one:
#   study_test.sh SCANPLAN PYTHON PART
# starts a local Dask scheduler with 2 worker processes, runs a study of 3 parts (PART and
# two boxes of a mesh) x 2 scanner presets and a broken part on it, and checks that
# - every good row's plan.json is the plan `scanplan plan` makes of it alone (seconds aside);
# - the broken part's rows hold its error, and the study exits 3 with its tables written;
# - the study run again on this machine reuses the plans done and plans only the failed.
set -eu
scanplan=$1 python=$2
export SCANPLAN_PYTHON="$python"
work=$(mktemp -d)
cluster=
trap 'if [ -n "$cluster" ]; then kill "$cluster" 2>/dev/null || true; fi; rm -rf "$work"' EXIT
cd "$work"
cp "$3" disc.stp
# Two boxes as ASCII STL: 120 x 80 x 40 mm and 60 x 60 x 60 mm.
"$python" - <<'PY'
def box(path, sx, sy, sz):
    v = [(x, y, z) for x in (0, sx) for y in (0, sy) for z in (0, sz)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    with open(path, "w") as f:
        f.write("solid box\n")
        for a, b, c, d in quads:
            for tri in ((a, b, c), (a, c, d)):
                f.write("facet normal 0 0 0\nouter loop\n")
                for i in tri:
                    f.write("vertex %g %g %g\n" % v[i])
                f.write("endloop\nendfacet\n")
        f.write("endsolid box\n")
box("flat.stl", 120, 80, 40)
box("cube.stl", 60, 60, 60)
PY
echo "not a STEP file" > broken.stp
cat > study.yaml <<'YAML'
parts: [disc.stp, flat.stl, cube.stl, broken.stp]
scanners: [generic-structured-light, laser-line]
registration: false
YAML
"$python" -c "
from distributed import LocalCluster
import time
cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
print(cluster.scheduler_address, flush=True)
time.sleep(600)
" > scheduler.txt 2> cluster.log &
cluster=$!
for i in $(seq 100); do [ -s scheduler.txt ] && break; sleep 0.1; done
address=$(head -1 scheduler.txt)
case "$address" in tcp://*) ;; *) echo "study_test: no scheduler"; cat cluster.log; exit 1 ;; esac

code=0
"$scanplan" -q study study.yaml -o out --dask "$address" > study.txt || code=$?
cat study.txt
[ "$code" -eq 3 ] || { echo "study_test: the study exited $code, not 3 (a row failed)"; exit 1; }
grep -q "8 plans: 6 planned, 0 reused, 2 failed" study.txt || { echo "study_test: counts"; exit 1; }
[ "$(grep -c ',failed,.*broken.stp: not a STEP file' out/study.csv)" -eq 2 ] ||
  { echo "study_test: the broken part's rows do not hold its error"; cat out/study.csv; exit 1; }
grep -q 'href="plans/disc__laser-line/report.html"' out/study.html ||
  { echo "study_test: the table does not link the reports"; exit 1; }

# Each good plan, planned alone by the CLI, is the same (seconds aside).
names= jobs=
for part in disc.stp flat.stl cube.stl; do
  for scanner in generic-structured-light laser-line; do
    name="${part%.*}__$scanner"
    names="$names $name"
    "$scanplan" -q -j 1 plan "$part" --scanner "$scanner" --no-registration --no-report \
      -o "alone/$name" > /dev/null &
    jobs="$jobs $!"
  done
done
for job in $jobs; do wait "$job"; done
for name in $names; do
  "$python" - "out/plans/$name/plan.json" "alone/$name/plan.json" <<'PY'
import json, sys
def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items()
                if "seconds" not in k and k not in ("file", "absolute_file")}
    if isinstance(o, list):
        return [strip(v) for v in o]
    return o
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
if a != b:
    sys.exit("study_test: %s differs from the plan made alone" % sys.argv[1])
PY
done

# Run again here: the plans done are reused, the broken part tried again.
code=0
"$scanplan" -q study study.yaml -o out --jobs 2 > again.txt || code=$?
grep -q "8 plans: 0 planned, 6 reused, 2 failed" again.txt || { cat again.txt; exit 1; }
echo "study_test: ok"
