#!/usr/bin/env bash
# The main job: installs the dependencies, builds the Release preset, runs
# every validation scene listed in tools/validation/runs.txt into out/NAME.csv,
# and writes the validation report (figures and error tables) to out/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash tools/setup.sh

log=build/reproduce-build.log
mkdir -p build out
echo "reproduce: building the release preset (log: $log)"
if ! { cmake --preset release && cmake --build --preset release; } >"$log" 2>&1; then
  tail -n 60 "$log" >&2
  echo "reproduce: build failed (full log: $log)" >&2
  exit 1
fi

XFDEM=build/release/tools/xfdem
while read -r name scene overrides; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  sets=()
  for kv in $overrides; do
    [[ "$kv" == \#* ]] && break
    sets+=(--set "$kv")
  done
  echo "reproduce: $name: xfdem run $scene${sets[*]:+ ${sets[*]}} --csv out/$name.csv"
  "$XFDEM" run "$scene" "${sets[@]}" --csv "out/$name.csv"
done < tools/validation/runs.txt

/usr/bin/python3 tools/validation/report.py --out out

# The 2D plate: a quarter plate with a hole (static), a strip cut by a tied
# crack and a strip with an edge crack (its tip enriched), written as VTK (cut
# cells split by side), drawn as von Mises fields; the edge crack's tip also
# on its own, on a log scale.
plates=()
for scene in plate_hole plate_crack plate_edge_crack; do
  rm -rf "out/vtk/$scene"
  echo "reproduce: $scene: xfdem run scenes/$scene.json --csv out/$scene.csv --vtk out/vtk/$scene"
  "$XFDEM" run "scenes/$scene.json" --csv "out/$scene.csv" --vtk "out/vtk/$scene"
  plates+=("$scene=out/vtk/$scene")
done
/usr/bin/python3 tools/validation/plate_figures.py --out out --window plate_edge_crack=0,1,2.5,3.5 "${plates[@]}"

# The heap (docs/dem.md): 600 disks settle for each friction and rolling
# friction of the sweep (twelve runs, about half a minute on one core); the
# angle of repose fitted to each pile's free surface. The 3D column collapse
# takes a few minutes: its own command is in docs/dem.md.
/usr/bin/python3 tools/validation/heap.py run --cli "$XFDEM" --work out/heap --figure out/heap_repose.png

# The figures the README and docs/ show, copied where they find them.
mkdir -p docs/figures
for fig in v1_fig6_trajectories v2_fig8_tip case1_fig9_10 case2_fig11_14 plate_hole_von_mises plate_edge_crack_window_von_mises heap_repose; do
  cp "out/$fig.png" "docs/figures/$fig.png"
done
echo "reproduce: copied the README figures to docs/figures/"
