#!/usr/bin/env python3
"""Figures of the 2D plate's stress fields, from the files `xfdem run --vtk`
writes (docs/xfem2d.md, "Output for viewing").

    plate_figures.py --out DIR [--window NAME=x0,x1,y0,y1 ...] NAME=VTK_DIR [NAME=VTK_DIR ...]

For each NAME, reads the last sample of VTK_DIR/NAME.pvd (the plate's pieces:
uncut cells as quads, cut cells split on each side of a discontinuity) and
draws the von Mises stress on the deformed pieces (displacement magnified so
that the largest one is 4 % of the plate's size) to DIR/NAME_von_mises.png.
Pieces in a void are not in the files, so a hole shows as a hole and an
opened crack as a gap. With a --window for NAME, draws only that part of the
plate, on a logarithmic colour scale (a crack tip's singular field spans
decades), to DIR/NAME_window_von_mises.png. Prints, per plate, the largest
von Mises stress and where it is.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402


def data_array(parent, name=None):
    for array in parent.iter("DataArray"):
        if name is None or array.get("Name") == name:
            values = np.array(array.text.split(), dtype=float)
            components = int(array.get("NumberOfComponents", "1"))
            return values.reshape(-1, components) if components > 1 else values
    raise KeyError(name)


def last_plate_file(vtk_dir, name):
    collection = ET.parse(os.path.join(vtk_dir, name + ".pvd")).getroot()
    files = [d.get("file") for d in collection.iter("DataSet") if "_plate_" in d.get("file")]
    if not files:
        raise SystemExit(f"plate_figures: {vtk_dir}/{name}.pvd lists no plate file")
    return os.path.join(vtk_dir, files[-1])


def read_plate(path):
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
    points = data_array(piece.find("Points"))[:, :2]
    displacement = data_array(piece.find("PointData"), "displacement")[:, :2]
    von_mises = data_array(piece.find("CellData"), "von_mises")
    cells = piece.find("Cells")
    connectivity = data_array(cells, "connectivity").astype(int)
    offsets = data_array(cells, "offsets").astype(int)
    starts = np.concatenate(([0], offsets[:-1]))
    polygons = [connectivity[s:e] for s, e in zip(starts, offsets)]
    return points, displacement, von_mises, polygons


def draw(name, vtk_dir, out_dir, window=None):
    points, displacement, von_mises, polygons = read_plate(last_plate_file(vtk_dir, name))
    if window is not None:
        x0, x1, y0, y1 = window
        centres = np.array([points[p].mean(axis=0) for p in polygons])
        inside = (centres[:, 0] >= x0) & (centres[:, 0] <= x1) & (centres[:, 1] >= y0) & (centres[:, 1] <= y1)
        if not inside.any():
            sys.exit(f"plate_figures: the window {window} of {name} holds no piece of the plate")
        polygons = [p for p, keep in zip(polygons, inside) if keep]
        von_mises = von_mises[inside]
        extent = max(x1 - x0, y1 - y0)
        largest = max(np.abs(displacement[p]).max() for p in polygons)
    else:
        extent = np.ptp(points, axis=0).max()
        largest = np.abs(displacement).max()
    scale = 0.04 * extent / largest if largest > 0 else 0.0
    deformed = points + scale * displacement
    fig, ax = plt.subplots(figsize=(7, 5.5))
    positive = von_mises[von_mises > 0]
    norm = LogNorm(vmin=positive.min() / 1e6, vmax=positive.max() / 1e6) if window is not None and positive.size else None
    collection = PolyCollection([deformed[p] for p in polygons], array=np.maximum(von_mises, 0) / 1e6,
                                cmap="viridis", norm=norm, edgecolors="face", linewidths=0.2)
    ax.add_collection(collection)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{name}: von Mises stress (MPa{', log scale' if norm else ''}), displacement x {scale:.3g}")
    fig.colorbar(collection, ax=ax, shrink=0.85)
    path = os.path.join(out_dir, f"{name}{'_window' if window is not None else ''}_von_mises.png")
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)
    worst = int(np.argmax(von_mises))
    centre = points[polygons[worst]].mean(axis=0)
    print(f"{name}: {len(polygons)} pieces; largest von Mises {von_mises[worst]:.6g} Pa "
          f"in the piece centred at ({centre[0]:.4g}, {centre[1]:.4g}) m; figure {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out")
    parser.add_argument("--window", action="append", default=[], metavar="NAME=x0,x1,y0,y1",
                        help="also draw this part of plate NAME (m), on a log scale")
    parser.add_argument("plates", nargs="+", metavar="NAME=VTK_DIR")
    args = parser.parse_args()
    windows = {}
    for item in args.window:
        name, sep, text = item.partition("=")
        try:
            bounds = [float(v) for v in text.split(",")]
        except ValueError:
            bounds = []
        if not sep or len(bounds) != 4 or not bounds[0] < bounds[1] or not bounds[2] < bounds[3]:
            sys.exit(f"plate_figures: --window expects NAME=x0,x1,y0,y1 with x0 < x1 and y0 < y1, got '{item}'")
        windows[name] = bounds
    os.makedirs(args.out, exist_ok=True)
    for item in args.plates:
        name, sep, vtk_dir = item.partition("=")
        if not sep or not name or not vtk_dir:
            sys.exit(f"plate_figures: expected NAME=VTK_DIR, got '{item}'")
        draw(name, vtk_dir, args.out)
        if name in windows:
            draw(name, vtk_dir, args.out, windows.pop(name))
    if windows:
        sys.exit(f"plate_figures: --window names no plate given: {', '.join(windows)}")


if __name__ == "__main__":
    main()
