#!/usr/bin/env python3
"""Work-precision figures and the settings guide, from the CSVs that
bench/work_precision.cpp (xfdem_work_precision) writes.

    work_precision.py [--out DIR]

Reads DIR/work_precision_<scene>.csv (default DIR: out), writes
DIR/work_precision_<scene>.png (log-log: error against run time per simulated
second, one line per integrator / setting, the Pareto front of all of them)
and DIR/work_precision_guide.md (the cheapest measured setting per error
budget), and prints:

- for V1 (k = 1e4 and 1e5), each integrator's cost at a relative error of 1e-6,
  interpolated between its two measured points around it in log-log (or, when
  its sweep stopped short of 1e-6, extrapolated from a least-squares line
  through its last four points, marked as such), and the ratio fixed-step
  velocity Verlet / the best;
- the guide table.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

SCENES = [
    ("v1_k1e4", "V1 drop test, k = 1e4 N/m: max relative apex error, 6 s"),
    ("v1_k1e5", "V1 drop test, k = 1e5 N/m: max relative apex error, 6 s"),
    ("v2", "V2 rod (30 el., X-FEM): tip error vs semi-discrete exact, 1 s"),
    ("case1", "Case I: error vs a run at dt/256, first second"),
    ("case2", "Case II: error vs a run at dt/256, first second"),
]
BUDGETS = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8]
TARGET = 1e-6


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    out = []
    for r in rows:
        def num(k):
            return float(r[k]) if r[k] != "" else math.nan
        out.append(dict(scene=r["scene"], method=r["method"], dt=num("dt"), n=int(r["n"]), beta=num("beta"),
                        gamma=num("gamma"), cost=num("seconds_per_simulated_second"), error=num("error")))
    return out


def setting(r):
    """Label of a line: everything but dt."""
    if r["scene"] == "v2":
        return f"Newmark β={r['beta']:g}, γ={r['gamma']:g}"
    if r["scene"].startswith("case"):
        return f"{r['method']}, n={r['n']}, β={r['beta']:g}, γ={r['gamma']:g}"
    return r["method"]


def describe(r):
    s = f"{setting(r)}, dt={r['dt']:g}"
    return s


def pareto(rows):
    """Non-dominated points: sorted by cost, keep those more accurate than every cheaper one."""
    front, best = [], math.inf
    for r in sorted(rows, key=lambda r: (r["cost"], r["error"])):
        if r["error"] < best:
            front.append(r)
            best = r["error"]
    return front


def cost_at(rows, target):
    """Cost of one setting at error `target`: (cost, how) or (nan, reason)."""
    pts = sorted((r for r in rows if r["error"] > 0 and math.isfinite(r["error"])), key=lambda r: r["cost"])
    for i, r in enumerate(pts):
        if r["error"] <= target:
            if i == 0:
                return r["cost"], "at its cheapest point"
            a = pts[i - 1]
            la, lb = math.log(a["error"]), math.log(r["error"])
            if la == lb:
                return r["cost"], "measured"
            s = (math.log(target) - la) / (lb - la)
            return math.exp(math.log(a["cost"]) + s * (math.log(r["cost"]) - math.log(a["cost"]))), "interpolated"
    tail = pts[-4:]
    if len(tail) < 2:
        return math.nan, "too few points"
    x = np.log([r["error"] for r in tail])
    y = np.log([r["cost"] for r in tail])
    slope, icept = np.polyfit(x, y, 1)
    if slope >= 0:
        return math.nan, "error does not fall with cost"
    return float(math.exp(icept + slope * math.log(target))), (
        f"extrapolated (last 4 points, cost ∝ error^{slope:.2f}; smallest error measured "
        f"{min(r['error'] for r in pts):.2e})")


def plot(scene, title, rows, out_dir, extra=None):
    runs = [r for r in rows if math.isfinite(r["cost"]) and r["error"] > 0]
    groups = {}
    for r in runs:
        groups.setdefault(setting(r), []).append(r)
    fig, ax = plt.subplots(figsize=(8.5, 6))
    many = len(groups) > 10
    cmap = plt.get_cmap("tab20" if many else "tab10")
    for i, (label, rs) in enumerate(groups.items()):
        rs = sorted(rs, key=lambda r: -r["dt"])
        style = "--" if ("γ=0.6" in label and scene.startswith("case")) else "-"
        ax.plot([r["error"] for r in rs], [r["cost"] for r in rs], style, marker="o", ms=3, lw=1,
                color=cmap(i % cmap.N), label=label)
    front = pareto(runs)
    ax.plot([r["error"] for r in front], [r["cost"] for r in front], color="k", lw=3, alpha=0.3,
            label="Pareto front (all settings)")
    for r in rows:
        if r["method"] == "reference_floor":
            ax.axvline(r["error"], color="gray", ls=":", lw=1)
            ax.text(r["error"], ax.get_ylim()[1], " reference's own error (bound)", rotation=90, va="top",
                    fontsize=7, color="gray")
    if scene.startswith("v1"):
        ax.axvline(TARGET, color="r", ls=":", lw=1)
    if extra:
        extra(ax)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("error (relative; see title)  →  more accurate")
    ax.set_ylabel("run time per simulated second (s)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=6.5 if many else 8, loc="upper left", ncol=2 if many else 1)
    fig.tight_layout()
    path = os.path.join(out_dir, f"work_precision_{scene}.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out"), help="folder of the CSVs and the outputs")
    args = ap.parse_args()

    data = {}
    for scene, _ in SCENES:
        path = os.path.join(args.out, f"work_precision_{scene}.csv")
        if os.path.isfile(path):
            data[scene] = read(path)
        else:
            print(f"work_precision: missing {path} (run xfdem_work_precision first)", file=sys.stderr)
    if not data:
        return 1

    figures = []
    for scene, title in SCENES:
        if scene not in data:
            continue
        extra = None
        if scene == "v2":
            sp = os.path.join(args.out, "work_precision_v2_spatial.csv")
            if os.path.isfile(sp):
                with open(sp, newline="") as f:
                    spatial = {int(r["elements"]): float(r["error"]) for r in csv.DictReader(f)}
                if 30 in spatial:
                    def extra(ax, e=spatial[30]):
                        ax.axvline(e, color="gray", ls=":", lw=1)
                        ax.text(e, ax.get_ylim()[1], " spatial error of 30 elements vs the continuum", rotation=90,
                                va="top", fontsize=7, color="gray")
        figures.append(plot(scene, title, data[scene], args.out, extra))

    # ---- the 10x question on V1 ----
    lines = []
    for scene in ("v1_k1e4", "v1_k1e5"):
        if scene not in data:
            continue
        by = {}
        for r in data[scene]:
            by.setdefault(r["method"], []).append(r)
        lines.append(f"{scene}: run time per simulated second at relative apex error {TARGET:g}")
        costs = {}
        for m, rs in by.items():
            c, how = cost_at(rs, TARGET)
            costs[m] = c
            lines.append(f"  {m:17s} {c:10.3e} s/s  ({how})")
        others = {m: c for m, c in costs.items() if m != "verlet" and math.isfinite(c)}
        if "verlet" in costs and others:
            best = min(others, key=others.get)
            lines.append(f"  verlet / best ({best}) = {costs['verlet'] / others[best]:.3g}")
    print("\n".join(lines))
    print()

    # ---- guide: cheapest measured setting per error budget ----
    md = ["| scene | error budget | cheapest measured setting | error | run time per simulated second |",
          "|---|---|---|---|---|"]
    for scene, _ in SCENES:
        if scene not in data:
            continue
        runs = [r for r in data[scene] if math.isfinite(r["cost"])]
        for b in BUDGETS:
            ok = [r for r in runs if r["error"] <= b]
            if not ok:
                continue
            r = min(ok, key=lambda r: r["cost"])
            md.append(f"| {scene} | {b:g} | {describe(r)} | {r['error']:.2e} | {r['cost']:.2e} s |")
    guide = "\n".join(md)
    print(guide)
    with open(os.path.join(args.out, "work_precision_guide.md"), "w") as f:
        f.write("# Work-precision: cheapest measured setting per error budget\n\n" + guide + "\n\n"
                + "```\n" + "\n".join(lines) + "\n```\n")
    print()
    for p in figures + [os.path.join(args.out, "work_precision_guide.md")]:
        print(f"wrote {os.path.relpath(p, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
