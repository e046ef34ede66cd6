#!/usr/bin/env python3
"""Reruns coupled scenes at Δt/k and prints how far their total energy rises
above its start: the check that separates an integrator's own error, which
falls with Δt, from energy an exchange creates, which does not.

    /usr/bin/python3 tools/validation/energy_dt_refinement.py [--cli build/release/tools/xfdem]
        [--probe E] [--factors 1 2 4 8 16] SCENE.json [SCENE.json ...]

Each scene (for example those `spec2d_variants.py -k free --keep DIR` keeps
when its undamped, frictionless `free` scenes fail "energy never rises") is
run through the CLI with time.dt divided by each factor, the output interval
and end unchanged; the energy probe (the column named by --probe, the one
`spec2d_variants.py` writes) is read from the CSV. Prints per run the largest
rise above the start and the rise at the end, both relative to the start.
Prints only; asserts nothing.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.path.join(ROOT, "build", "release", "tools", "xfdem")


def rises(cli, scene, factor, probe, work):
    s = json.loads(json.dumps(scene))
    s["time"]["dt"] /= factor
    path = os.path.join(work, "scene.json")
    out = os.path.join(work, "out.csv")
    with open(path, "w") as f:
        json.dump(s, f)
    r = subprocess.run([cli, "run", path, "--csv", out], capture_output=True, text=True)
    if r.returncode != 0:
        return None, r.stderr.strip().splitlines()[0] if r.stderr.strip() else f"exit {r.returncode}"
    with open(out) as f:
        energy = [float(row[probe]) for row in csv.DictReader(f)]
    e0 = energy[0]
    return ((max(energy) - e0) / e0, (energy[-1] - e0) / e0), None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=CLI)
    ap.add_argument("--probe", default="E")
    ap.add_argument("--factors", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    print(f"{'scene':40s} {'dt/k':>5s} {'largest rise':>13s} {'rise at end':>13s}")
    with tempfile.TemporaryDirectory() as work:
        for path in args.scenes:
            with open(path) as f:
                scene = json.load(f)
            name = os.path.splitext(os.path.basename(path))[0]
            for k in args.factors:
                got, error = rises(args.cli, scene, k, args.probe, work)
                if got is None:
                    print(f"{name:40s} {k:5d} refused: {error}")
                    continue
                print(f"{name:40s} {k:5d} {got[0]:13.3e} {got[1]:13.3e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
