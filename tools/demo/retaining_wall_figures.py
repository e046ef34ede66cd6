#!/usr/bin/env python3
"""Figures of the retaining-wall demonstration (docs/coupled2d.md, "Demonstration").

    retaining_wall_figures.py --out DIR WALL.csv WALL_VTK_DIR INTACT.csv INTACT_VTK_DIR

WALL.csv / WALL_VTK_DIR: `xfdem run scenes/demo/retaining_wall.json --csv ... --vtk ...`;
INTACT.csv / INTACT_VTK_DIR: the same for scenes/demo/retaining_wall_intact.json.
Writes to DIR:
  retaining_wall_scene.png    the last sample of the cracked wall: the disks coloured by the
                              magnitude of their contacts' elastic normal
                              forces, the wall's von Mises stress on its
                              deformed pieces (the crack and the weep hole as
                              gaps), and a close-up of the crack tip;
  retaining_wall_history.png  K_I and K_II of the crack's tip, the crack
                              mouth's opening, the backfill's horizontal
                              thrust on the wall and the wall top's
                              deflection over time, cracked and intact.
Prints the numbers docs/coupled2d.md quotes.

The disks' forces are recomputed here from the files' positions and radii:
k* δ for every overlap (k* = k/2 between two disks of stiffness k, k against
a plane or the wall), the elastic part of the linear law only (the dashpot's
part is not in the files); the wall's back face is placed at its deformed
position (the plate's displacement along its back face, interpolated in y).
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection, PolyCollection  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "validation"))
from plate_figures import data_array, read_plate  # noqa: E402  (the VTK readers of the plate's figures)
from retaining_wall import BACK_X, CRACK_FACE_TIP_X, CRACK_TIP_X, CRACK_Y, DENSITY, STIFFNESS, WALL_H, WALL_X  # noqa: E402


def last_files(vtk_dir):
    pvd = [f for f in os.listdir(vtk_dir) if f.endswith(".pvd")]
    if len(pvd) != 1:
        raise SystemExit(f"retaining_wall_figures: expected one .pvd in {vtk_dir}, found {pvd}")
    sets = list(ET.parse(os.path.join(vtk_dir, pvd[0])).getroot().iter("DataSet"))
    time = max(float(d.get("timestep")) for d in sets)
    last = [d.get("file") for d in sets if float(d.get("timestep")) == time]
    plate = next(f for f in last if "_plate_" in f)
    particles = next(f for f in last if "_particles_" in f)
    return time, os.path.join(vtk_dir, plate), os.path.join(vtk_dir, particles)


def read_particles(path):
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
    x = data_array(piece.find("Points"))[:, :2]
    return x, data_array(piece.find("PointData"), "radius"), data_array(piece.find("PointData"), "velocity")[:, :2]


def contact_forces(x, r, points, displacement):
    """Σ |k* δ| over each disk's contacts (disks, floor, back plane, the wall's back face)."""
    force = np.zeros(len(r))
    for start in range(0, len(r), 256):
        d = np.hypot(x[start:start + 256, None, 0] - x[None, :, 0], x[start:start + 256, None, 1] - x[None, :, 1])
        overlap = r[start:start + 256, None] + r[None, :] - d
        np.fill_diagonal(overlap[:, start:start + 256], 0.0)
        force[start:start + 256] += 0.5 * STIFFNESS * np.clip(overlap, 0, None).sum(axis=1)
    force += STIFFNESS * np.clip(r - x[:, 1], 0, None)
    force += STIFFNESS * np.clip(r - (BACK_X - x[:, 0]), 0, None)
    face = np.abs(points[:, 0] - WALL_X) < 1e-9
    order = np.argsort(points[face, 1])
    face_x = WALL_X + np.interp(x[:, 1], points[face, 1][order], displacement[face, 0][order])
    force += STIFFNESS * np.clip(r - (x[:, 0] - face_x), 0, None)
    return force


def read_csv(path):
    names = open(path).readline().strip().split(",")
    values = np.loadtxt(path, delimiter=",", skiprows=1)
    return {n: values[:, k] for k, n in enumerate(names)}


def thrust(c):
    return sum(v for k, v in c.items() if k.startswith("fw_"))


def scene_figure(vtk_dir, out):
    time, plate_file, particle_file = last_files(vtk_dir)
    points, displacement, von_mises, polygons = read_plate(plate_file)
    x, r, v = read_particles(particle_file)
    force = contact_forces(x, r, points, displacement)
    fig, (ax, zoom) = plt.subplots(2, 1, figsize=(9, 11), gridspec_kw={"height_ratios": [2.3, 1]})
    for a, window in ((ax, None), (zoom, (0.05, WALL_X, CRACK_Y - 0.1, CRACK_Y + 0.1))):
        keep = range(len(polygons))
        if window is not None:
            centres = np.array([points[p].mean(axis=0) for p in polygons])
            keep = [k for k, c in enumerate(centres)
                    if window[0] <= c[0] <= window[1] and window[2] <= c[1] <= window[3]]
        vm = np.maximum(von_mises[list(keep)], 1.0) / 1e3
        plates = PolyCollection([points[polygons[k]] for k in keep],
                                array=vm, cmap="viridis", edgecolors="face", linewidths=0.2,
                                norm=LogNorm(vmin=vm.min(), vmax=vm.max()))
        a.add_collection(plates)
        fig.colorbar(plates, ax=a, shrink=0.7, label="wall: von Mises stress (kPa, log)")
        a.set_aspect("equal")
    disks = PatchCollection([Circle(c, rad) for c, rad in zip(x, r)], array=force, cmap="inferno_r",
                            edgecolors="none")
    ax.add_collection(disks)
    fig.colorbar(disks, ax=ax, shrink=0.7, label="disks: Σ|k δ| of their contacts (N)")
    ax.set_xlim(-0.05, BACK_X + 0.02)
    ax.set_ylim(-0.02, WALL_H + 0.05)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"t = {time:.3g} s: the backfill against the cracked wall (drawn undeformed: its displacement "
                 f"is at most {np.abs(displacement).max() * 1e6:.3g} µm)")
    zoom.set_xlim(0.05, WALL_X)
    zoom.set_ylim(CRACK_Y - 0.1, CRACK_Y + 0.1)
    zoom.set_title("the crack, its two tips and the pieces of the cut cells")
    zoom.set_xlabel("x (m)")
    fig.savefig(os.path.join(out, "retaining_wall_scene.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)
    worst = int(np.argmax(von_mises))
    print(f"scene at t = {time:.6g} s: {len(r)} disks, largest disk speed {np.hypot(v[:, 0], v[:, 1]).max():.3g} m/s, "
          f"largest disk contact-force sum {force.max():.4g} N; largest von Mises {von_mises[worst]:.4g} Pa "
          f"at ({points[polygons[worst]].mean(axis=0)[0]:.4g}, {points[polygons[worst]].mean(axis=0)[1]:.4g}) m")
    # The backfill's unit weight from the files (disk mass ρ π r²) over its area up to its top.
    mass = DENSITY * np.pi * r ** 2
    top = np.sort(x[:, 1] + r)[-50:].mean()
    gamma = mass.sum() * 9.81 / ((BACK_X - WALL_X) * top)
    return gamma, top


def history_figure(wall, intact, out, gamma, height):
    fig, axes = plt.subplots(3, 1, figsize=(8, 10), sharex=True)
    t = wall["t"]
    axes[0].plot(t, wall["K_I_face"] / 1e3, label="K_I, outer tip")
    axes[0].plot(t, wall["K_II_face"] / 1e3, label="K_II, outer tip")
    axes[0].plot(t, wall["K_I_inner"] / 1e3, label="K_I, inner tip")
    axes[0].set_ylabel("stress intensity (kPa √m)")
    ax2 = axes[0].twinx()
    ax2.plot(t, wall["opening"] * 1e6, "k:", label="opening")
    ax2.set_ylabel(f"crack opening at x = 0.22 m (µm, dotted)")
    axes[0].legend(loc="upper left")
    axes[0].set_title(f"the crack (y = {CRACK_Y} m, tips at x = {CRACK_TIP_X} and {CRACK_FACE_TIP_X} m)")
    axes[1].plot(t, thrust(wall) / 1e3, label="cracked wall (X-FEM)")
    axes[1].plot(intact["t"], thrust(intact) / 1e3, "--", label="intact wall (plain FE)")
    axes[1].axhline(0.5 * gamma * height ** 2 / 1e3, color="grey", lw=0.8, label="½ γ H² (K = 1)")
    axes[1].set_ylabel("horizontal thrust on the wall (kN per m)")
    axes[1].legend()
    axes[2].plot(t, wall["top_ux"] * 1e6, label="cracked wall (X-FEM)")
    axes[2].plot(intact["t"], intact["top_ux"] * 1e6, "--", label="intact wall (plain FE)")
    axes[2].set_ylabel("wall top displacement x (µm)")
    axes[2].set_xlabel("t (s)")
    axes[2].legend()
    fig.savefig(os.path.join(out, "retaining_wall_history.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)
    for name, c in (("cracked", wall), ("intact", intact)):
        h = thrust(c)
        print(f"{name}: at t = {c['t'][-1]:.4g} s thrust {h[-1]:.6g} N/m (K = thrust / (½ γ H²) = "
              f"{h[-1] / (0.5 * gamma * height ** 2):.3g}, γ = {gamma:.5g} N/m³, H = {height:.4g} m), "
              f"top u_x {c['top_ux'][-1]:.6g} m, base σ_yy back {c['base_syy'][-1]:.6g} Pa, "
              f"front {c['front_syy'][-1]:.6g} Pa, kinetic energy {c['E_kinetic'][-1]:.4g} J")
    # The wall rings (average-acceleration Newmark keeps its vibration's
    # energy): single samples mix the load's response with that ringing, so
    # the comparison is of means over the last fifth of the run.
    late = t >= 0.8 * t[-1]
    for name, c in (("cracked", wall), ("intact", intact)):
        keys = ["top_ux", "base_syy", "front_syy"] + (["K_I_face", "K_II_face", "K_I_inner", "opening"]
                                                      if "opening" in c else [])
        parts = [f"thrust {thrust(c)[late].mean():.5g} N/m (sd {thrust(c)[late].std():.3g})"]
        parts += [f"{k} {c[k][late].mean():.5g} (sd {c[k][late].std():.3g})" for k in keys]
        print(f"{name}, means over t >= {0.8 * t[-1]:.3g} s ({late.sum()} rows): " + ", ".join(parts))
    for name, c in (("cracked", wall), ("intact", intact)):
        h, drag = thrust(c), sum(v for k, v in c.items() if k.startswith("ft_"))
        late = c["t"] >= 0.8 * c["t"][-1]
        print(f"{name}: first force on the wall at t = {c['t'][np.argmax(h > 0)]:.4g} s; thrust peak {h.max():.5g} N/m "
              f"at t = {c['t'][np.argmax(h)]:.4g} s; top u_x least {c['top_ux'].min():.4g} m at "
              f"t = {c['t'][np.argmin(c['top_ux'])]:.4g} s; kinetic energy peak {c['E_kinetic'].max():.5g} J; "
              f"late means: drag {drag[late].mean():.4g} N/m, thrust / (½ γ H²) "
              f"{h[late].mean() / (0.5 * gamma * height ** 2):.3g}")
    print(f"cracked: outer K_I peak at t = {t[np.argmax(wall['K_I_face'])]:.4g} s, opening peak at "
          f"t = {t[np.argmax(wall['opening'])]:.4g} s")
    print(f"cracked at t = {t[-1]:.4g} s: outer tip K_I {wall['K_I_face'][-1]:.6g} Pa√m, "
          f"K_II {wall['K_II_face'][-1]:.6g} Pa√m; inner tip K_I {wall['K_I_inner'][-1]:.6g} Pa√m; "
          f"opening {wall['opening'][-1]:.6g} m; peaks over the run: outer K_I {wall['K_I_face'].max():.6g}, "
          f"opening {wall['opening'].max():.6g}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="docs/figures")
    parser.add_argument("wall_csv")
    parser.add_argument("wall_vtk")
    parser.add_argument("intact_csv")
    parser.add_argument("intact_vtk")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    gamma, height = scene_figure(args.wall_vtk, args.out)
    time, plate_file, _ = last_files(args.intact_vtk)
    points, _, von_mises, polygons = read_plate(plate_file)
    worst = int(np.argmax(von_mises))
    centre = points[polygons[worst]].mean(axis=0)
    print(f"intact wall at t = {time:.6g} s: largest von Mises {von_mises[worst]:.4g} Pa at "
          f"({centre[0]:.4g}, {centre[1]:.4g}) m")
    history_figure(read_csv(args.wall_csv), read_csv(args.intact_csv), args.out, gamma, height)


if __name__ == "__main__":
    main()
