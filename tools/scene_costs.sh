#!/usr/bin/env bash
# Per-step cost of every scene in scenes/ on one and two workers, as fast as
# possible, with xfdem_rt: prints a markdown table (median, p99 and worst step).
# Usage: tools/scene_costs.sh [BUILD_DIR]   (default build/release)
set -euo pipefail
cd "$(dirname "$0")/.."
rt=${1:-build/release}/tools/xfdem_rt
echo "| scene | workers | steps | median | p99 | worst |"
echo "|---|---:|---:|---:|---:|---:|"
for scene in scenes/*.json; do
  for threads in 1 2; do
    # A scene the harness refuses (or that stops on a step status) is listed as such.
    if ! report=$("$rt" "$scene" --threads "$threads" 2>/dev/null); then
      printf '| %s | %s | not run (xfdem_rt failed) | | | |\n' "$(basename "$scene" .json)" "$threads"
      continue
    fi
    field() { awk -v k="$1:" '$1 == k { print $2 }' <<<"$report"; }
    printf '| %s | %s | %s | %s ns | %s ns | %s ns |\n' "$(basename "$scene" .json)" "$threads" \
      "$(field steps)" "$(field step_median_ns)" "$(field step_p99_ns)" "$(field step_max_ns)"
  done
done
