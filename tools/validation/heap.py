#!/usr/bin/env python3
"""The heap: disks poured on a floor, and the angle of repose of the pile they
form against the friction μ and the rolling friction μ_r (docs/dem.md, "The
heap and the column collapse").

    heap.py scene [--out scenes/granular/heap_2d.json] [--particles 600] [--name heap_2d]
    heap.py scene --out scenes/granular/heap_2d_small.json --particles 150 --name heap_2d_small --end 1.5
    heap.py run --cli build/release/tools/xfdem [--scene scenes/granular/heap_2d.json]
                [--figure docs/figures/heap_repose.png] [--work DIR]

`scene` writes the scene: N polydisperse disks (radii uniform in
[0.75, 1.25] r0, seeded) placed at random without overlap (area fraction 0.5)
inside a triangle with 40° sides standing on the floor, released at rest: the
heap is steeper than it can stand, collapses and settles at its angle of
repose. (A pour from a height, the column of disks falling as one, splashed
the pile flat at a few degrees: impact speeds of metres per second.) `run` runs
the CLI for each (μ, μ_r) of the sweep (`--set dem.contact.friction=...`),
reads the particles' final positions from its --vtk output and fits the free
surface (`repose_angle`); it prints one line per run and draws the figure.

The angle: the free surface is the top of the highest disk in each bin of
width one mean diameter (y + r); the pile is the run of occupied bins around the highest
one; on each flank a straight line is fitted (least squares) to the surface
between 20 % and 80 % of the pile's height, and the angle of repose is the
mean of the two slopes' angles. tests/long/heap_long_test.cpp and
tests/dem/heap_test.cpp measure it the same way in C++.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import xml.etree.ElementTree as ET

R0 = 0.01  # m, the mean radius
DENSITY = 2500.0  # kg/m^3; a disk's mass per unit thickness is rho pi r^2
STIFFNESS = 1e7  # N/m per disk (a pair: 5e6 in series)
DT = 5e-5  # s; stable-step margin ~ 6 at the smallest disk (the build checks)
END = 3.0  # s: the heap has stopped (but for disks rolling away on the floor without rolling friction)
SIDE = 40.0  # deg, the sides of the triangle the disks start in


def make_scene(particles, name, end=END, seed=15):
    """Disks placed at random, without overlap, inside a triangle with 60° sides
    standing on the floor: a heap built steeper than any of the sweep's can stand."""
    rng = random.Random(seed)
    area = particles * math.pi * R0 * R0 / 0.5  # a loose packing, area fraction 0.5
    tan60 = math.tan(math.radians(SIDE))
    half_base = math.sqrt(area / tan60)
    base = 1.3 * R0
    items, placed = [], []
    cell = 2.5 * R0
    grid = {}
    while len(items) < particles:
        r = R0 * (0.75 + 0.5 * rng.random())
        y = base + rng.random() * half_base * tan60
        x = (2 * rng.random() - 1) * half_base
        if abs(x) > (half_base * tan60 - (y - base)) / tan60 - r or y - base < 0:
            continue  # outside the triangle
        gx, gy = math.floor(x / cell), math.floor(y / cell)
        near = [placed[k] for i in (-1, 0, 1) for j in (-1, 0, 1) for k in grid.get((gx + i, gy + j), [])]
        if any((x - px) ** 2 + (y - py) ** 2 < (r + pr) ** 2 for px, py, pr in near):
            continue
        grid.setdefault((gx, gy), []).append(len(placed))
        placed.append((x, y, r))
        k = len(items)
        items.append({"name": f"d{k}", "mass": DENSITY * math.pi * r * r, "radius": r, "stiffness": STIFFNESS,
                      "position": [x, y], "velocity": [0.0, 0.0]})
    return {
        "name": name,
        "dimension": 2,
        "gravity": [0.0, -9.81],
        "time": {"end": end, "dt": DT},
        "dem": {
            "integrator": "verlet",
            "contact": {"law": "linear", "damping_ratio": 0.3, "friction": 0.5,
                        "tangential_stiffness_ratio": 2.0 / 7.0, "rolling_friction": 0.0},
            "particles": items,
            "planes": [{"name": "floor", "point": [0.0, 0.0], "normal": [0.0, 1.0]}],
        },
        "output": {"every": end, "probes": [{"name": "E_kinetic", "quantity": "energy", "of": "kinetic"}]},
    }


def last_particles(vtk_dir, name):
    """(x, y, r) of every particle in the last sample of VTK_DIR/NAME.pvd."""
    collection = ET.parse(os.path.join(vtk_dir, name + ".pvd")).getroot()
    files = [d.get("file") for d in collection.iter("DataSet") if "_particles_" in d.get("file")]
    if not files:
        raise SystemExit(f"heap: {vtk_dir}/{name}.pvd lists no particle file")
    piece = ET.parse(os.path.join(vtk_dir, files[-1])).getroot().find("UnstructuredGrid/Piece")
    points = [float(v) for v in piece.find("Points").find("DataArray").text.split()]
    radius = None
    for array in piece.find("PointData").iter("DataArray"):
        if array.get("Name") == "radius":
            radius = [float(v) for v in array.text.split()]
    xs, ys = points[0::3], points[1::3]
    return list(zip(xs, ys, radius))


def surface(discs, bin_width):
    """Top of the highest disk per bin of width bin_width: {bin index: height}."""
    top = {}
    for x, y, r in discs:
        b = math.floor(x / bin_width)
        top[b] = max(top.get(b, 0.0), y + r)
    return top


def line_slope(points):
    n = len(points)
    sx = sum(p[0] for p in points)
    sy = sum(p[1] for p in points)
    sxx = sum(p[0] * p[0] for p in points)
    sxy = sum(p[0] * p[1] for p in points)
    return (n * sxy - sx * sy) / (n * sxx - sx * sx)


def repose_angle(discs):
    """(angle in degrees, pile height, surface points used) from the final positions."""
    w = 2 * sum(r for _, _, r in discs) / len(discs)  # the mean diameter
    top = surface(discs, w)
    peak = max(top, key=lambda b: top[b])
    height = top[peak]
    flanks = []
    for step in (-1, 1):
        pts = []
        b = peak
        while b in top:  # the run of occupied bins from the peak outwards
            h = top[b]
            if 0.2 * height <= h <= 0.8 * height:
                pts.append((abs(b - peak) * w, h))
            b += step
        flanks.append(pts)
    angles = []
    for pts in flanks:
        if len(pts) < 3:
            return 0.0, height, flanks
        angles.append(math.degrees(math.atan(-line_slope(pts))))
    return sum(angles) / 2, height, flanks


# The sweep: μ at μ_r = 0, then μ_r at μ = 0.5; μ = μ_r = 0 is the frictionless pile.
SWEEP = [(0.0, 0.0), (0.1, 0.0), (0.2, 0.0), (0.5, 0.0), (1.0, 0.0), (0.1, 0.1), (0.2, 0.1), (0.5, 0.1), (1.0, 0.1), (0.5, 0.05), (0.5, 0.2), (0.5, 0.4)]


def run(args):
    os.makedirs(args.work, exist_ok=True)
    results, deposits = [], {}
    for mu, mur in SWEEP:
        tag = f"mu{mu}_mur{mur}"
        vtk = os.path.join(args.work, tag)
        csv = os.path.join(args.work, tag + ".csv")
        cmd = [args.cli, "run", args.scene, "--set", f"dem.contact.friction={mu}", "--set",
               f"dem.contact.rolling_friction={mur}", "--csv", csv, "--vtk", vtk]
        subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
        with open(args.scene) as f:
            name = json.load(f)["name"]
        discs = last_particles(vtk, name)
        angle, height, flanks = repose_angle(discs)
        with open(csv) as f:
            kinetic = float(f.read().strip().splitlines()[-1].split(",")[1])
        results.append((mu, mur, angle, height, kinetic))
        deposits[(mu, mur)] = (discs, angle)
        diameter = 2 * sum(r for _, _, r in discs) / len(discs)
        print(f"mu {mu:4.2f} mu_r {mur:4.2f}: angle of repose {angle:5.2f} deg, pile height {height / diameter:5.2f} "
              f"mean diameters, final kinetic energy {kinetic:.2e} J/m", flush=True)
    if args.figure:
        draw(results, deposits, args)
    return results


def draw(results, deposits, args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle

    fig = plt.figure(figsize=(10, 7))
    left = fig.add_subplot(2, 2, 1)
    right = fig.add_subplot(2, 2, 2, sharey=left)
    for k, rolling in enumerate(sorted({mur for _, mur, _, _, _ in results if mur in (0.0, 0.1)})):
        line = sorted((mu, a) for mu, mur, a, _, _ in results if mur == rolling and mu > 0)
        left.plot([m for m, _ in line], [a for _, a in line], "o-", color=f"C{k}", label=f"μ_r = {rolling:g}")
    left.set_xlabel("friction μ")
    left.set_ylabel("angle of repose (deg)")
    left.legend(fontsize=8)
    left.grid(alpha=0.3)
    line = sorted((mur, a) for mu, mur, a, _, _ in results if mu == 0.5)
    right.plot([m for m, _ in line], [a for _, a in line], "s-", color="C2")
    right.set_xlabel("rolling friction μ_r (μ = 0.5)")
    right.grid(alpha=0.3)
    bottom = fig.add_subplot(2, 1, 2)
    shown = [(0.0, 0.0), (0.5, 0.0), (0.5, 0.2)]
    offset = 0.0
    for k, key in enumerate(shown):
        discs, angle = deposits[key]
        y0 = offset
        bottom.add_collection(PatchCollection([Circle((x, y + y0), r) for x, y, r in discs], color=f"C{k}", lw=0))
        bottom.text(-0.95, y0 + 0.2, f"μ = {key[0]:g}, μ_r = {key[1]:g}: {angle:.1f}°", fontsize=8)
        offset += 0.33
    bottom.set_xlim(-1.0, 1.0)
    bottom.set_ylim(0, offset)
    bottom.set_aspect("equal")
    bottom.set_yticks([])
    bottom.set_xlabel("x (m); final deposits, stacked")
    fig.suptitle(f"2D heap: {args.particles_in_scene} polydisperse disks released in a 40° triangle "
                 "(scenes/granular/heap_2d.json)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.figure, dpi=110)
    print(f"wrote {args.figure}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    s = sub.add_parser("scene")
    s.add_argument("--out", default="scenes/granular/heap_2d.json")
    s.add_argument("--particles", type=int, default=600)
    s.add_argument("--name", default="heap_2d")
    s.add_argument("--end", type=float, default=END)
    r = sub.add_parser("run")
    r.add_argument("--cli", required=True)
    r.add_argument("--scene", default="scenes/granular/heap_2d.json")
    r.add_argument("--figure", default="docs/figures/heap_repose.png")
    r.add_argument("--work", default="out/heap")
    args = parser.parse_args()
    if args.command == "scene":
        with open(args.out, "w") as f:
            json.dump(make_scene(args.particles, args.name, args.end), f, indent=1)
            f.write("\n")
        print(f"wrote {args.out}")
    else:
        with open(args.scene) as f:
            args.particles_in_scene = len(json.load(f)["dem"]["particles"])
        run(args)


if __name__ == "__main__":
    sys.exit(main())
