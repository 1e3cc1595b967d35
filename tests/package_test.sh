#!/bin/sh
# The installed package as another project uses it:
#   package_test.sh BUILD_DIR SOURCE_DIR PART
# installs BUILD_DIR into a temporary prefix, builds examples/consumer against it, plans
# PART with it, and checks the plan's coverage with the installed CLI, all from outside the source
# tree and without SCANPLAN_DATA (the presets are the library's own).
set -eu
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset SCANPLAN_DATA
cmake --install "$1" --prefix "$work/prefix" >/dev/null
# SCANPLAN_CONSUMER_FLAGS: compiler flags the library was built with that its users need
# too (the sanitizers' runtime).
cmake -S "$2/examples/consumer" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_CXX_FLAGS="${SCANPLAN_CONSUMER_FLAGS:-}" >/dev/null
cmake --build "$work/build" >/dev/null
cp "$3" "$work/part.stp"
cd "$work"
out=$(./build/plan_part part.stp plan.json)
echo "$out"
case "$out" in
  *" views, "*" samples measured") ;;
  *) echo "package_test: the consumer did not plan" >&2; exit 1 ;;
esac
views=$(echo "$out" | cut -d' ' -f1)
[ "$views" -gt 0 ] || { echo "package_test: no views" >&2; exit 1; }
# The views measure what the plan says (its views do not all register: exit 3 is fine).
check=$(./prefix/bin/scanplan -q verify plan.json part.stp) || [ $? -eq 3 ]
echo "$check"
echo "$check" | grep -q "coverage check  *as planned" ||
  { echo "package_test: the installed CLI does not confirm the plan's coverage" >&2; exit 1; }
