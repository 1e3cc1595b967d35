#!/usr/bin/env bash
# Builds the fuzzers (the `fuzz` preset: clang, libFuzzer, AddressSanitizer and UBSan) and
# runs each for SECONDS (default 600) on a copy of its corpus in tests/fuzz/. Inputs that
# crash are left in build/fuzz/findings/<fuzzer>/: add each to the corpus with its fix.
#   scripts/fuzz.sh [SECONDS] [FUZZER ...]     fuzzers: mesh cad points_csv spec plan
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
fuzzers=("$@")
[ ${#fuzzers[@]} -gt 0 ] || fuzzers=(mesh cad points_csv spec plan)

scripts/install-deps.sh
# The fuzzers need clang and its libFuzzer, which the build itself does not.
if ! command -v clang++ >/dev/null; then
  echo "fuzz: installing clang"
  $( [ "$(id -u)" -eq 0 ] || echo sudo ) apt-get install -y --no-install-recommends clang
fi
cmake --preset fuzz
cmake --build --preset fuzz --target "${fuzzers[@]/#/fuzz_}"
export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
for name in "${fuzzers[@]}"; do
  work=build/fuzz/corpus/$name findings=build/fuzz/findings/$name
  mkdir -p "$work" "$findings"
  cp -n tests/fuzz/"$name"/* "$work"/
  echo "fuzzing $name for $seconds s"
  build/fuzz/fuzz/fuzz_"$name" "$work" -max_total_time="$seconds" -max_len=65536 \
    -artifact_prefix="$findings"/ -print_final_stats=1 2>&1 | tail -n 12
done
