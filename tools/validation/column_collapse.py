#!/usr/bin/env python3
"""The 3D column collapse: spheres in a cylindrical column released on a floor,
the final runout against the column's aspect ratio a = H_i/R_i, beside the
published fit for axisymmetric collapses (docs/dem.md, "The heap and the column
collapse").

    column_collapse.py --cli build/release/tools/xfdem [--figure docs/figures/column_collapse.png]
                       [--work out/column_collapse] [--aspect 0.5 1 2 3 4]

For each rolling friction μ_r and aspect ratio the script writes a scene (WORK/column_a<a>.json: spheres
on a face-centred cubic lattice of spacing 2.04 r_max inside a cylinder of
radius R_i = 0.1 m, radii uniform in [0.85, 1] r_max, seeded, so nothing
overlaps at the start), runs the CLI on it with --vtk, and reads the final
positions. The runout R_inf is the radius about the column's axis within which
99 % of the spheres lie (a few spheres that roll away from the deposit do not
set it); the figure plots (R_inf - R_i)/R_i against a with the fit of Lube et
al. (J. Fluid Mech. 508, 2004) for axisymmetric collapses,
(R_inf - R_i)/R_i = 1.24 a for a < 1.7 and 1.6 a^(1/2) above.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys

R_MAX = 0.01  # m, the largest sphere's radius
R_COLUMN = 0.1  # m, the column's radius R_i (about 5.4 mean diameters)
DENSITY = 2500.0
STIFFNESS = 2e5  # N/m per sphere: the deepest overlap stays below a few % of r
DT = 4e-5  # s
END = 1.5  # s


def make_scene(aspect, rolling, seed=2005):
    rng = random.Random(seed)
    height = aspect * R_COLUMN
    nn = 2.04 * R_MAX  # nearest-neighbour distance of the lattice
    a = nn * math.sqrt(2.0)  # the FCC cube
    items = []
    n_side = int(R_COLUMN / (a / 2)) + 2
    n_up = int(height / (a / 2)) + 2
    for j in range(n_up):
        for i in range(-n_side, n_side + 1):
            for k in range(-n_side, n_side + 1):
                if (i + j + k) % 2:
                    continue
                x, y, z = i * a / 2, R_MAX + j * a / 2, k * a / 2
                if x * x + z * z > (R_COLUMN - R_MAX) ** 2 or y > height - R_MAX:
                    continue
                r = R_MAX * (0.85 + 0.15 * rng.random())
                items.append({"name": f"s{len(items)}", "mass": DENSITY * 4.0 / 3.0 * math.pi * r ** 3, "radius": r,
                              "stiffness": STIFFNESS, "position": [x, y, z], "velocity": [0.0, 0.0, 0.0]})
    return {
        "name": f"column_a{aspect:g}_mur{rolling:g}",
        "dimension": 3,
        "gravity": [0.0, -9.81, 0.0],
        "time": {"end": END, "dt": DT},
        "dem": {
            "integrator": "verlet",
            "contact": {"law": "linear", "damping_ratio": 0.3, "friction": 0.5,
                        "tangential_stiffness_ratio": 2.0 / 7.0, "rolling_friction": rolling},
            # spheres that roll away spread the grid's bounding box
            "capacities": {"max_grid_cells": 4000000},
            "particles": items,
            "planes": [{"name": "floor", "point": [0.0, 0.0, 0.0], "normal": [0.0, 1.0, 0.0]}],
        },
        "output": {"every": END, "probes": [{"name": "E_kinetic", "quantity": "energy", "of": "kinetic"}]},
    }


def runout(spheres, fraction=0.99):
    """(radius holding `fraction` of the spheres, the largest radius, height of the deposit)."""
    radii = sorted(math.hypot(x, z) for x, y, z, r in spheres)
    top = max(y + r for x, y, z, r in spheres)
    return radii[min(len(radii) - 1, int(math.ceil(fraction * len(radii))) - 1)], radii[-1], top


def lube(a):
    return 1.24 * a if a < 1.7 else 1.6 * math.sqrt(a)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", required=True)
    parser.add_argument("--figure", default="docs/figures/column_collapse.png")
    parser.add_argument("--work", default="out/column_collapse")
    parser.add_argument("--aspect", type=float, nargs="+", default=[0.5, 1.0, 2.0, 3.0, 4.0])
    parser.add_argument("--rolling", type=float, nargs="+", default=[0.1, 0.3])
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    rows = []
    for rolling, aspect in [(mur, a) for mur in args.rolling for a in args.aspect]:
        scene = make_scene(aspect, rolling)
        path = os.path.join(args.work, scene["name"] + ".json")
        with open(path, "w") as f:
            json.dump(scene, f)
        vtk = os.path.join(args.work, scene["name"])
        csv = vtk + ".csv"
        subprocess.run([args.cli, "run", path, "--csv", csv, "--vtk", vtk], check=True, stderr=subprocess.DEVNULL)
        spheres = read_3d(vtk, scene["name"])
        r99, r_max, top = runout(spheres)
        with open(csv) as f:
            kinetic = float(f.read().strip().splitlines()[-1].split(",")[1])
        spread = (r99 - R_COLUMN) / R_COLUMN
        rows.append((aspect, rolling, spread, (r_max - R_COLUMN) / R_COLUMN, top / R_COLUMN))
        print(f"mu_r = {rolling:g}, a = {aspect:4.2f}: {len(spheres):5d} spheres, (R_inf - R_i)/R_i = {spread:5.2f} (99 %), "
              f"{(r_max - R_COLUMN) / R_COLUMN:5.2f} (farthest sphere), fit {lube(aspect):5.2f}; "
              f"H_inf/R_i = {top / R_COLUMN:4.2f}; final kinetic energy {kinetic:.1e} J", flush=True)
    if args.figure:
        draw(rows, args.figure)


def read_3d(vtk_dir, name):
    import xml.etree.ElementTree as ET

    collection = ET.parse(os.path.join(vtk_dir, name + ".pvd")).getroot()
    files = [d.get("file") for d in collection.iter("DataSet") if "_particles_" in d.get("file")]
    piece = ET.parse(os.path.join(vtk_dir, files[-1])).getroot().find("UnstructuredGrid/Piece")
    points = [float(v) for v in piece.find("Points").find("DataArray").text.split()]
    radius = next([float(v) for v in a.text.split()] for a in piece.find("PointData").iter("DataArray")
                  if a.get("Name") == "radius")
    return list(zip(points[0::3], points[1::3], points[2::3], radius))


def draw(rows, figure):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    grid = [0.3 + 0.01 * k for k in range(471)]
    ax.plot(grid, [lube(a) for a in grid], "k-", lw=1, label="Lube et al. 2004 fit: 1.24a, 1.6a$^{1/2}$ (a > 1.7)")
    for k, rolling in enumerate(sorted({r[1] for r in rows})):
        mine = [r for r in rows if r[1] == rolling]
        ax.plot([r[0] for r in mine], [r[2] for r in mine], "o-", color=f"C{k}",
                label=f"xfdem, μ$_r$ = {rolling:g}: 99 % of the spheres")
        ax.plot([r[0] for r in mine], [r[3] for r in mine], "x", color=f"C{k}",
                label=f"xfdem, μ$_r$ = {rolling:g}: farthest sphere")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ticks = sorted({r[0] for r in rows})
    ax.set_xticks(ticks)
    ax.set_xticklabels([f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_xlabel("aspect ratio a = H$_i$/R$_i$")
    ax.set_ylabel("runout (R$_\\infty$ − R$_i$)/R$_i$")
    ax.set_title("3D column collapse of spheres, μ = 0.5, R$_i$ ≈ 5.4 mean diameters", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
    print(f"wrote {figure}")


if __name__ == "__main__":
    sys.exit(main())
