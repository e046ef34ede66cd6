#!/usr/bin/env bash
# Builds the two libFuzzer targets (preset `fuzz`: clang 14, libFuzzer, ASan,
# UBSan) and runs each for SECONDS (default 60), one after the other:
#   scene_loader_fuzz      arbitrary bytes as a scene file (seeds: scenes/*.json)
#   snapshot_restore_fuzz  arbitrary bytes as a snapshot (seeds: valid snapshots
#                          of its fixed worlds, written by the fuzzer itself)
# Prints, per fuzzer, the executions reached (libFuzzer's
# stat::number_of_executed_units). Exits non-zero on a finding (crash, hang,
# sanitizer report), leaving the input under build/fuzz/findings/; replay it
# with build/fuzz/fuzz/<fuzzer> <file>. The corpora grow under
# build/fuzz/corpus/ and are reused by the next run. docs/fuzzing.md.
#   usage: bash tools/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[[ $seconds =~ ^[0-9]+$ && $seconds -gt 0 ]] || { echo "usage: tools/fuzz.sh [SECONDS]" >&2; exit 2; }

bash tools/setup.sh
mkdir -p build
blog=build/fuzz-build.log start=$SECONDS
echo "fuzz: configure + build (log: $blog)"
if ! { cmake --preset fuzz && cmake --build --preset fuzz; } </dev/null >"$blog" 2>&1; then
  tail -n 80 "$blog" >&2
  echo "fuzz: build FAILED after $((SECONDS - start)) s (full log: $blog)" >&2
  exit 1
fi
echo "fuzz: built in $((SECONDS - start)) s"

bin=build/fuzz/fuzz
corpus=build/fuzz/corpus
findings=build/fuzz/findings
mkdir -p "$corpus/scene_loader" "$corpus/snapshot_restore" "$findings"
cp scenes/*.json fuzz/corpus/scene_loader/* "$corpus/scene_loader/"
cp fuzz/corpus/snapshot_restore/* "$corpus/snapshot_restore/"
"$bin/snapshot_restore_fuzz" -write_seeds="$corpus/snapshot_restore" >/dev/null

status=0
run() {
  local name=$1 log=build/fuzz/$1.log
  echo "fuzz: [$name] ${seconds} s"
  # -timeout: one input running longer than 10 s is a hang (a finding).
  if "$bin/${name}_fuzz" "$corpus/$name" -max_total_time="$seconds" -seed="${XFDEM_FUZZ_SEED:-0}" -timeout=10 -rss_limit_mb=2048 \
       -print_final_stats=1 -artifact_prefix="$findings/${name}-" </dev/null >"$log" 2>&1; then
    local execs
    execs=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+).*/\1/p' "$log" | tail -n 1)
    echo "fuzz: [$name] ${execs:-?} executions in ${seconds} s, no finding (log: $log)"
  else
    tail -n 60 "$log" >&2
    echo "fuzz: [$name] FINDING (input under $findings/, log: $log)" >&2
    status=1
  fi
}
run scene_loader
run snapshot_restore
exit $status
