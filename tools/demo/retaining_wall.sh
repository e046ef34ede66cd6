#!/usr/bin/env bash
# The retaining-wall demonstration (docs/coupled2d.md, "Demonstration"): runs
# scenes/demo/retaining_wall.json and its intact counterpart through the CLI (CSV
# and VTK into out/demo/), then draws docs/figures/retaining_wall_*.png.
# About two minutes of one core per scene on an idle machine; both run at once.
# Needs a release build (cmake --preset release && cmake --build --preset release).
#
#   bash tools/demo/retaining_wall.sh [VTK_EVERY]
#
# VTK_EVERY (s, default 0.005, every CSV row) thins the VTK files only through
# output.every, which the CSV shares: 0.005 writes about 260 MB per scene.
set -euo pipefail
cd "$(dirname "$0")/../.."
cli=build/release/tools/xfdem
[[ -x $cli ]] || { echo "retaining_wall.sh: no $cli; build the release preset first" >&2; exit 2; }
every=${1:-0.005}
mkdir -p out/demo
pids=()
for scene in retaining_wall retaining_wall_intact; do
  rm -rf "out/demo/vtk_$scene"
  echo "retaining_wall.sh: $cli run scenes/demo/$scene.json --set output.every=$every --csv out/demo/$scene.csv --vtk out/demo/vtk_$scene"
  "$cli" run "scenes/demo/$scene.json" --set "output.every=$every" --csv "out/demo/$scene.csv" --vtk "out/demo/vtk_$scene" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid"; done
/usr/bin/python3 tools/demo/retaining_wall_figures.py --out docs/figures \
  out/demo/retaining_wall.csv out/demo/vtk_retaining_wall out/demo/retaining_wall_intact.csv out/demo/vtk_retaining_wall_intact
