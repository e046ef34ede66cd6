#!/usr/bin/python3
"""Where a coupled 2D step's time goes, from `perf record -g` samples.

    perf record -F 999 -g -o perf.data -- COMMAND
    /usr/bin/python3 tools/demo/perf_stages.py perf.data [--under run_wall_steps]

Keeps the samples whose call chain passes through --under (default
run_wall_steps, the timed steps of BM_Coupled2dRetainingWall in
bench/bm_demo2d.cpp; `coupled2d_step` for a whole CLI run) and prints, per
stage, the share of those samples whose chain passes through the stage's
function (inclusive, as callgrind_annotate --inclusive=yes counts).
"""
import argparse
import collections
import subprocess
import sys

# (label, substrings of its symbols: a chain through any of them counts),
# shown in this order. The DEM's step is named by dem_step and, where
# unwinding skips that frame, by granular_step, which it calls.
STAGES = [
    ("the fixed point's passes (window_pass)", ["window_pass"]),
    ("  the disks' contacts with the boundary (disk_contacts)", ["disk_contacts"]),
    ("    closest points and broad phase (plate_boundary_contacts)", ["plate_boundary_contacts"]),
    ("    the force's spread onto the plate (plate_spread_force)", ["plate_spread_force"]),
    ("  the DEM's substeps (dem_step, granular_step)", ["dem_step<2>", "granular_step<2>"]),
    ("    disk-disk pairs (granular_pairs)", ["granular_pairs<2"]),
    ("  the plate's steps (plate_step)", ["plate_step"]),
    ("  the plate's start acceleration (plate_start_acceleration)", ["plate_start_acceleration"]),
    ("  the window's copies of the disks (dem_copy_state)", ["dem_copy_state"]),
    ("the boundary's positions (plate_boundary_positions)", ["plate_boundary_positions"]),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("data")
    ap.add_argument("--under", default="run_wall_steps")
    args = ap.parse_args()
    script = subprocess.run(["perf", "script", "-i", args.data, "-F", "ip,sym", "--no-demangle"],
                            capture_output=True, text=True)
    if script.returncode != 0:
        sys.exit(script.stderr)
    demangled = subprocess.run(["c++filt"], input=script.stdout, capture_output=True, text=True).stdout
    total = 0
    hits = collections.Counter()
    for chain in demangled.split("\n\n"):
        if args.under not in chain:
            continue
        total += 1
        for label, symbols in STAGES:
            if any(symbol in chain for symbol in symbols):
                hits[label] += 1
    if total == 0:
        sys.exit(f"perf_stages: no sample passes through {args.under}")
    print(f"{total} samples under {args.under}")
    for label, _ in STAGES:
        print(f"{100.0 * hits[label] / total:6.1f} %  {label}")


if __name__ == "__main__":
    main()
