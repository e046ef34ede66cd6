#!/usr/bin/python3
"""Instructions per step of a scene, by function, from callgrind.

Runs the CLI under `valgrind --tool=callgrind` to two end times and prints,
per step between them, the difference of the inclusive (and self) instruction
counts of the functions that make up a step (docs/benchmarks.md). Build-time
work cancels in the difference.

    /usr/bin/python3 tools/callgrind_steps.py [--build build/release] SCENE T0 T1

e.g. `tools/callgrind_steps.py scenes/case2_xfem.json 8 9` (Case II, both
particles resting on the rod). Needs valgrind and callgrind_annotate.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

# Shown in this order when present (substring of callgrind's function name).
FUNCTIONS = [
    ("the whole process", "PROGRAM TOTALS"),
    ("coupled_step", "xfdem::coupled_step("),
    ("  particle substeps (dem_steps)", "xfdem::StepStatus xfdem::dem_steps<1>("),
    ("  particle substeps (dem_step)", "xfdem::StepStatus xfdem::dem_step<1>("),
    ("  bar_step", "xfdem::bar_step("),
    ("    Newmark loops (self)", "xfdem::xfem::newmark_step<"),
    ("    K u (negated_product)", "xfdem::xfem::SymmetricBand::negated_product("),
    ("    K u (subtract_product)", "xfdem::xfem::SymmetricBand::subtract_product("),
    ("    LDLt solve", "xfdem::xfem::BandLdlt::solve("),
    ("  bar_adjust_step_input", "xfdem::bar_adjust_step_input("),
    ("  bar_resolve_acceleration", "xfdem::bar_resolve_acceleration("),
    ("  copies of the particles' state", "void xfdem::dem_copy_state<1>("),  # not the walk it calls
    ("CSV numbers (to_chars)", "std::to_chars("),
]
SELF = {"    Newmark loops (self)"}


def counts(out_file, inclusive):
    text = subprocess.run(["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}", "--threshold=100",
                           out_file], capture_output=True, text=True, check=True).stdout
    result = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+(?:\(\s*[\d.]+%\)\s+)?(.*)", line)
        if m and m.group(2):
            result[m.group(2)] = result.get(m.group(2), 0) + int(m.group(1).replace(",", ""))
    return result


def lookup(table, key):
    return sum(v for name, v in table.items() if key in name)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build/release")
    parser.add_argument("scene")
    parser.add_argument("t0", type=float)
    parser.add_argument("t1", type=float)
    args = parser.parse_args()
    dt = json.load(open(args.scene))["time"]["dt"]
    steps = round((args.t1 - args.t0) / dt)
    if steps <= 0:
        sys.exit("callgrind_steps: T1 must be later than T0 by at least one step")
    cli = os.path.join(args.build, "tools", "xfdem")
    tables = []
    with tempfile.TemporaryDirectory() as tmp:
        for t in (args.t0, args.t1):
            out = os.path.join(tmp, f"{t}.out")
            subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", cli, "run", args.scene,
                            "--set", f"time.end={t}", "--csv", os.path.join(tmp, "run.csv")],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            tables.append((counts(out, True), counts(out, False)))
    print(f"{args.scene}, t = {args.t0} .. {args.t1} s: {steps} steps; instructions per step")
    for label, key in FUNCTIONS:
        which = 1 if label in SELF else 0
        per_step = (lookup(tables[1][which], key) - lookup(tables[0][which], key)) / steps
        if per_step != 0:
            print(f"  {label:<36} {per_step:10.0f}")


if __name__ == "__main__":
    main()
