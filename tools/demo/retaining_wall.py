#!/usr/bin/env python3
"""Writes the retaining-wall demonstration scenes (docs/coupled2d.md, "Demonstration").

A concrete cantilever wall 0.4 m thick and 1.6 m tall, held along its base,
with a free crack 0.15 m long inside it, parallel to the base, its outer tip
0.11 m under its back face (two tips, so K_I is defined at both: the
stress_intensity probe wants a tip 4 cells from the boundary; a crack that
reaches the back face, where the disks touch its mouth, ends the run with
coupling_unstable: docs/coupled2d.md), and a circular weep hole, and a granular backfill of
frictional disks behind it, between the wall's back face, a floor plane and a
back plane, released from rest in a loose staggered lattice, settling under
gravity against the wall.

    scenes/demo/retaining_wall.json         the X-FEM wall (crack and weep hole)
    scenes/demo/retaining_wall_intact.json  the same wall without them: no
                                       enrichment, plain Q4 finite elements

The disks' radii and the lattice's jitter come from a fixed linear
congruential generator, so the scenes are the same bytes on every machine.
Usage: python3 tools/demo/retaining_wall.py [--out scenes/demo]

In scenes/demo/, not scenes/: the suite runs every scene directly in
scenes/ 10 000 steps ten times over (RunAfterRun), which these scenes,
at about 10 ms a step, would turn into hours.
"""
import argparse
import json
import re
import math
import os

WALL_X = 0.4           # the wall's back face (x = 0 its front)
WALL_H = 1.6
BACK_X = 1.6           # the back plane, the backfill's far side
FILL_TOP = 1.45        # no disk centre above this
R_MAX, R_MIN = 0.012, 0.008
GAP = 0.002            # clearance between lattice sites beyond two largest radii
DENSITY = 2000.0       # kg/m³ of a disk (mass per unit thickness ρ π r²)
STIFFNESS = 1e6        # N/m, every disk (linear law)
CRACK_Y = 0.31         # between the node rows 0.3 and 0.325
CRACK_TIP_X = 0.14     # the inner tip, between the node columns 0.125 and 0.15
CRACK_FACE_TIP_X = 0.29  # the outer tip, 0.11 m under the back face (between the columns 0.275 and 0.3)
CELLS = [16, 64]       # cells of 0.025 m
NEAR_WALL = 3          # disks of the first NEAR_WALL lattice columns get a wall-force probe


class Lcg:
    """Knuth's MMIX LCG: deterministic across machines and Python versions."""

    def __init__(self, seed):
        self.state = seed

    def uniform(self):
        self.state = (6364136223846793005 * self.state + 1442695040888963407) % (1 << 64)
        return (self.state >> 11) / float(1 << 53)


def disks():
    rng = Lcg(17)
    pitch = 2 * R_MAX + GAP
    out = []
    j = 0
    while True:
        y = R_MAX + GAP / 2 + j * pitch * math.sqrt(3) / 2   # hexagonal rows: neighbours a pitch apart
        if y > FILL_TOP:
            break
        shift = 0.5 * pitch * (j % 2)
        i = 0
        while True:
            x = WALL_X + R_MAX + GAP / 2 + shift + i * pitch
            if x + R_MAX + GAP / 2 > BACK_X:
                break
            r = R_MIN + (R_MAX - R_MIN) * rng.uniform()
            jitter = (rng.uniform() - 0.5) * (R_MAX - r)   # stays within the site
            # Rounded to a nanometre: short numbers in the scene, exact in binary alike.
            out.append({"name": "d%d" % len(out), "column": i, "radius": round(r, 9),
                        "position": [round(x + jitter, 9), round(y, 9)]})
            i += 1
        j += 1
    return out


def scene(name, cracked, particles):
    discontinuities = []
    probes = []
    if cracked:
        discontinuities = [
            {"name": "crack", "type": "crack", "points": [[CRACK_TIP_X, CRACK_Y], [CRACK_FACE_TIP_X, CRACK_Y]],
             "faces": "free"},
            {"name": "weep_hole", "type": "void", "circle": {"centre": [0.2, 0.9], "radius": 0.04}},
        ]
        probes += [
            {"name": "K_I_face", "quantity": "stress_intensity", "crack": "crack", "tip": "end", "mode": "I"},
            {"name": "K_II_face", "quantity": "stress_intensity", "crack": "crack", "tip": "end", "mode": "II"},
            {"name": "K_I_inner", "quantity": "stress_intensity", "crack": "crack", "tip": "start", "mode": "I"},
            {"name": "opening", "quantity": "crack_opening", "crack": "crack", "at": [0.22, CRACK_Y],
             "component": "normal"},
        ]
    probes += [
        {"name": "top_ux", "quantity": "displacement", "at": [WALL_X, WALL_H], "component": 0},
        {"name": "base_syy", "quantity": "stress", "at": [WALL_X - 0.0125, 0.0125], "component": "yy"},
        {"name": "front_syy", "quantity": "stress", "at": [0.0125, 0.0125], "component": "yy"},
        {"name": "px_particles", "quantity": "momentum", "of": "particles", "component": 0},
        {"name": "py_particles", "quantity": "momentum", "of": "particles", "component": 1},
        {"name": "px_continuum", "quantity": "momentum", "of": "continuum", "component": 0},
        {"name": "E_kinetic", "quantity": "energy", "of": "kinetic"},
    ]
    # The wall's load: each near-wall disk's force on the plate, normal (along
    # the back face's normal: the thrust) and tangential (the drag), and its
    # height (the thrust's moment about the crack's section).
    for p in particles:
        if p["column"] < NEAR_WALL:
            n = p["name"]
            probes += [{"name": "fw_" + n, "quantity": "contact_force", "between": [n, "plate"]},
                       {"name": "ft_" + n, "quantity": "contact_force", "between": [n, "plate"], "part": "tangential"},
                       {"name": "y_" + n, "quantity": "position", "particle": n, "component": 1}]
    return {
        "name": name,
        "dimension": 2,
        "gravity": [0.0, -9.81],
        "time": {"end": 1.0, "dt": 1e-4, "dem_substeps": 10},
        "dem": {
            "integrator": "symplectic_euler",
            "contact": {"law": "linear", "damping_ratio": 0.3, "friction": 0.5,
                        "tangential_stiffness_ratio": 0.8},
            "planes": [{"name": "floor", "point": [0.0, 0.0], "normal": [0.0, 1.0]},
                       {"name": "back", "point": [BACK_X, 0.0], "normal": [-1.0, 0.0]}],
            "particles": [
                {"name": p["name"], "mass": DENSITY * math.pi * p["radius"] ** 2, "radius": p["radius"],
                 "stiffness": STIFFNESS, "position": p["position"], "velocity": [0.0, 0.0]}
                for p in particles],
        },
        "continuum": {
            "type": "plate",
            "plane": "strain",
            "thickness": 1.0,
            "domain": {"min": [0.0, 0.0], "max": [WALL_X, WALL_H]},
            "cells": CELLS,
            "material": {"youngs_modulus": 3e10, "poisson_ratio": 0.2, "density": 2400.0},
            "analysis": "dynamic",
            "discontinuities": discontinuities,
            "supports": [{"edge": "bottom", "fix": ["x", "y"]}],
        },
        "output": {"every": 0.005, "probes": probes},
    }


def write(path, data):
    # One particle or probe per line: readable diffs, a file of a few hundred kB.
    lists = {}
    for block, key in ((data["dem"], "particles"), (data["output"], "probes")):
        tag = "@%s@" % key
        lists[tag] = ",\n".join("    " + json.dumps(item) for item in block[key])
        block[key] = [tag]
    text = json.dumps(data, indent=1)
    for tag, body in lists.items():
        text = re.sub(r"\n *" + re.escape(json.dumps(tag)), lambda m: "\n" + body, text)
    with open(path, "w") as f:
        f.write(text + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "demo"))
    args = ap.parse_args()
    particles = disks()
    write(os.path.join(args.out, "retaining_wall.json"), scene("retaining_wall", True, particles))
    write(os.path.join(args.out, "retaining_wall_intact.json"), scene("retaining_wall_intact", False, particles))
    print("%d disks, %d wall-force probes" % (len(particles), sum(p["column"] < NEAR_WALL for p in particles)))


if __name__ == "__main__":
    main()
