#!/usr/bin/env python3
"""Validation report: reads the CSVs of the runs listed in runs.txt, compares
them with the reference solutions, writes figures and error tables.

    report.py [--out DIR] [--runs FILE]

Writes DIR/*.png, DIR/validation_errors.csv (long format: case, run, k,
integrator, metric, value) and DIR/validation_errors.md, and prints the tables.
Exits non-zero if a CSV is missing or a case has no handler.

Each case (the run name's text before the first "_") has a handler module with
analyse(runs, out_dir, plt) -> (tables, long_rows, figures); add a case by
listing its runs in runs.txt and its handler in HANDLERS below.
"""
import argparse
import csv
import json
import os
import shlex
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import cases  # noqa: E402
import v1_drop  # noqa: E402
import v2_rod  # noqa: E402

HANDLERS = {
    v1_drop.CASE: v1_drop.analyse,
    v2_rod.CASE: v2_rod.analyse,
    **{case: cases.analyse for case in cases.CASES},
}


class Run:
    """One line of runs.txt: its scene (overrides applied) and its CSV columns."""

    def __init__(self, name, scene_path, overrides, out_dir):
        self.name, self.scene_path, self.overrides = name, scene_path, overrides
        self.case = name.split("_", 1)[0]
        self.csv_path = os.path.join(out_dir, name + ".csv")
        with open(os.path.join(ROOT, scene_path)) as f:
            self.scene = json.load(f)
        for kv in overrides:
            key, _, value = kv.partition("=")
            _set_path(self.scene, key, value, name)
        self.columns = None

    def load(self):
        with open(self.csv_path, newline="") as f:
            rows = list(csv.reader(f))
        header, data = rows[0], np.array(rows[1:], dtype=float)
        if data.ndim != 2 or data.shape[1] != len(header):
            raise ValueError(f"{self.csv_path}: malformed CSV")
        self.columns = {h: data[:, i] for i, h in enumerate(header)}

    def col(self, name):
        if name not in self.columns:
            raise KeyError(f"{self.csv_path}: no column '{name}' (have {', '.join(self.columns)})")
        return self.columns[name]

    def probe(self, quantity, particle=None, component=0):
        """Name of the first output probe of a particle's quantity."""
        for p in self.scene.get("output", {}).get("probes", []):
            if (p.get("quantity") == quantity and "particle" in p
                    and (particle is None or p["particle"] == particle)
                    and p.get("component", 0) == component):
                return p["name"]
        raise KeyError(f"{self.scene_path}: no probe of particle {quantity}")


def _set_path(obj, dotted, text, where):
    """Apply `--set a.b.0.c=VALUE` the way the CLI does (VALUE as JSON if it parses)."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError:
        value = text
    keys = dotted.split(".")
    for key in keys[:-1]:
        obj = obj[int(key)] if isinstance(obj, list) else obj.setdefault(key, {})
    last = keys[-1]
    if isinstance(obj, list):
        obj[int(last)] = value
    else:
        obj[last] = value


def read_runs(path, out_dir):
    runs = []
    with open(path) as f:
        for line in f:
            words = shlex.split(line, comments=True)
            if not words:
                continue
            if len(words) < 2:
                raise ValueError(f"{path}: '{line.strip()}': want NAME SCENE [KEY=VALUE ...]")
            runs.append(Run(words[0], words[1], words[2:], out_dir))
    return runs


def format_table(t):
    cols, rows = t["columns"], t["rows"]
    w = [max(len(c), *(len(r[i]) for r in rows)) for i, c in enumerate(cols)]
    lines = [t["title"], "  ".join(c.ljust(w[i]) for i, c in enumerate(cols))]
    lines.append("  ".join("-" * x for x in w))
    lines += ["  ".join(r[i].ljust(w[i]) for i in range(len(cols))) for r in rows]
    if t.get("note"):
        lines.append(t["note"])
    return "\n".join(lines)


def markdown_table(t):
    def cell(x):
        return x.replace("|", "\\|")
    lines = [f"**{t['title']}**", "", "| " + " | ".join(map(cell, t["columns"])) + " |",
             "|" + "|".join("---" for _ in t["columns"]) + "|"]
    lines += ["| " + " | ".join(map(cell, r)) + " |" for r in t["rows"]]
    if t.get("note"):
        lines += ["", t["note"]]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out"), help="CSV input and report output folder")
    ap.add_argument("--runs", default=os.path.join(HERE, "runs.txt"), help="the table of runs")
    args = ap.parse_args()

    runs = read_runs(args.runs, args.out)
    missing = [r.csv_path for r in runs if not os.path.isfile(r.csv_path)]
    if missing:
        for m in missing:
            print(f"report: missing {m}", file=sys.stderr)
        print("report: run tools/reproduce.sh first", file=sys.stderr)
        return 1
    unknown = sorted({r.case for r in runs} - set(HANDLERS))
    if unknown:
        print(f"report: no handler for case(s) {', '.join(unknown)}", file=sys.stderr)
        return 1

    tables, long_rows, figures = [], [], []
    for case, handler in HANDLERS.items():
        mine = [r for r in runs if r.case == case]
        if not mine:
            continue
        for r in mine:
            r.load()
        t, lr, fg = handler(mine, args.out, plt)
        tables += t
        long_rows += lr
        figures += fg

    with open(os.path.join(args.out, "validation_errors.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "run", "k", "integrator", "metric", "value"])
        for row in long_rows:
            w.writerow([repr(x) if isinstance(x, float) else x for x in row])
    with open(os.path.join(args.out, "validation_errors.md"), "w") as f:
        f.write("# Validation errors\n\n")
        f.write("\n\n".join(markdown_table(t) for t in tables) + "\n")

    print("\n\n".join(format_table(t) for t in tables))
    print()
    for p in figures + [os.path.join(args.out, "validation_errors.csv"),
                        os.path.join(args.out, "validation_errors.md")]:
        print(f"wrote {os.path.relpath(p, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
