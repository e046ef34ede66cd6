#!/usr/bin/env bash
# The test command: installs the dependencies, then builds and runs the test
# suite twice, in Release and under AddressSanitizer + UBSan (Debug), and
# ends with a short fuzzing run (tools/fuzz.sh 20: 20 s per fuzzer, clang).
# Build output goes to build/<preset>-build.log and is shown only on failure;
# ctest's summary lines are printed, its full output on failure.
# Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."

bash tools/setup.sh
mkdir -p build

passed=0 failed=0
count() {  # add up "N% tests passed, F tests failed out of T"
  local line f t
  line=$(grep -E 'tests passed, [0-9]+ tests? failed out of [0-9]+' "$1" | tail -n 1) || return 0
  f=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
  t=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")
  passed=$((passed + t - f)) failed=$((failed + f))
}

run_preset() {
  local preset=$1 blog=build/$1-build.log tlog=build/$1-ctest.log start=$SECONDS
  echo "test: [$preset] configure + build (log: $blog)"
  if ! { cmake --preset "$preset" && cmake --build --preset "$preset"; } </dev/null >"$blog" 2>&1; then
    tail -n 80 "$blog" >&2
    echo "test: [$preset] build FAILED after $((SECONDS - start)) s (full log: $blog)" >&2
    return 1
  fi
  local built=$SECONDS
  echo "test: [$preset] built in $((built - start)) s; ctest --preset $preset"
  if ! ctest --preset "$preset" </dev/null >"$tlog" 2>&1; then
    cat "$tlog" >&2
    count "$tlog"
    echo "test: [$preset] ctest FAILED after $((SECONDS - built)) s (log: $tlog)" >&2
    return 1
  fi
  # the summary: "N% tests passed, ...", label times, "Total Test time"
  sed -n '/tests passed/,$p' "$tlog"
  count "$tlog"
  echo "test: [$preset] tests ran in $((SECONDS - built)) s"
}

status=0
run_preset release || status=1
run_preset debug-asan || status=1
fuzz_start=$SECONDS
if XFDEM_FUZZ_SEED=1 bash tools/fuzz.sh 20 </dev/null; then  # a fixed seed: the same inputs every run
  echo "test: [fuzz] no finding in $((SECONDS - fuzz_start)) s (build + 2 x 20 s)"
else
  echo "test: [fuzz] FAILED after $((SECONDS - fuzz_start)) s" >&2
  status=1
fi
if [[ $status -ne 0 ]]; then
  echo "test: FAILED after $SECONDS s" >&2
else
  echo "test: release, debug-asan and fuzz passed in $SECONDS s"
fi
echo "test: $passed passed, $failed failed"
exit $status
