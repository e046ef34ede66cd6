#!/usr/bin/env python3
"""2D scene variants written from the 2D scene spec (not from scenes/), with
randomized numbers (fixed seeds), run through the CLI and compared with closed
forms or independent solutions computed here. The 2D counterpart of
spec_variants.py.

    /usr/bin/python3 tools/validation/spec2d_variants.py [--cli build/release/tools/xfdem] [-k FILTER]
        [-n VARIANTS] [--keep DIR]

Cases (each variant draws its geometry, material, mesh, integrator, law,
friction and rolling friction from wide ranges):
  tension   static plate under uniform edge traction, supports that allow the
            uniform field; with a crack parallel to the load (free, tied,
            unilateral faces) and an inclusion of the same material
  incline   a disk (sphere in 3D) on an inclined plane: rolling or sliding
  rest      a disk at rest on a supported plate under gravity, against a
            static run of the same plate with a point force at the contact
  free      a free plate with a void and a crack hit by frictional disks:
            momentum, and energy when nothing dissipates
  threads   --threads 1 and 2 give the same CSV bytes
Prints one row per check: its error, the tolerance and why. Exits 1 if any
check exceeds its tolerance, 2 if the CLI fails on a scene the spec says is
valid. Scenes of failed checks are kept under --keep (default: a new
directory in the system's temporary directory, printed at the end).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

G = 9.81
EPS = np.finfo(float).eps
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.path.join(ROOT, "build", "release", "tools", "xfdem")
TMP = None
KEEP = None
N = 48
INTEGRATORS = ("symplectic_euler", "verlet", "rk4", "abm4", "abm4_events")


class CliError(Exception):
    pass


def keep(name):
    """Copy a scene (and its CSV) to the keep directory; return its path."""
    global KEEP
    if KEEP is None:
        KEEP = tempfile.mkdtemp(prefix="spec2d_variants_")
    os.makedirs(KEEP, exist_ok=True)
    for ext in (".json", ".csv"):
        src = os.path.join(TMP, name + ext)
        if os.path.exists(src):
            shutil.copy(src, KEEP)
    return os.path.join(KEEP, name + ".json")


def run(scene, name=None, threads=None):
    """Write the scene, run the CLI, return {column: array} from its CSV
    (header t,<probe names>; rows at every multiple of output.every)."""
    name = name or scene["name"]
    path = os.path.join(TMP, name + ".json")
    csv = os.path.join(TMP, name + ".csv")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    cmd = [CLI, "run", path, "--csv", csv]
    if threads:
        cmd += ["--threads", str(threads)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise CliError(f"{name}: exit {p.returncode}: {p.stderr.strip()[:400]} (scene kept: {keep(name)})")
    with open(csv) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    probes = [pr["name"] for pr in scene["output"]["probes"]]
    if header != ["t"] + probes:
        raise CliError(f"{name}: header {header} is not t,{','.join(probes)} (scene kept: {keep(name)})")
    data = np.array([[float(v) for v in r] for r in rows])
    out = {h: data[:, i] for i, h in enumerate(header)}
    if "time" in scene and "every" in scene["output"]:
        every, end = scene["output"]["every"], scene["time"]["end"]
        n = int(round(end / every))
        if len(rows) != n + 1 or np.max(np.abs(out["t"] - every * np.arange(n + 1))) > 1e-9 * end:
            raise CliError(f"{name}: {len(rows)} rows, expected {n + 1} at k*{every} (scene kept: {keep(name)})")
    elif len(rows) != 1 or out["t"][0] != 0.0:
        raise CliError(f"{name}: a static run writes one row at t = 0, got {len(rows)} (scene kept: {keep(name)})")
    return out


RESULTS = []


def report(case, err, tol, why, scene=None):
    ok = bool(err <= tol)  # NaN fails
    RESULTS.append((case, err, tol, ok, why))
    kept = ""
    if not ok and scene:
        kept = f"  [scene kept: {keep(scene)}]"
    print(f"{'ok  ' if ok else 'FAIL'} {case:52s} {err:10.3e} {tol:10.3e}  {why}{kept}", flush=True)


def logu(rng, a, b):
    return float(10 ** rng.uniform(math.log10(a), math.log10(b)))


def elastic_strains(plane, E, nu, s):
    """Uniaxial stress s along a, free across b: (e_aa, e_bb); plane strain
    holds e_zz = 0 (sigma_zz = nu s)."""
    if plane == "stress":
        return s / E, -nu * s / E
    return s * (1 - nu * nu) / E, -nu * (1 + nu) * s / E


# --------------------------------------------------------------------------
# 1. static plate, uniform tension (closed form)
# --------------------------------------------------------------------------
def cases_tension():
    rng = np.random.default_rng(2101)
    kinds = ("none", "crack_free", "crack_tied", "crack_unilateral", "inclusion", "crack_free+inclusion",
             "crack_tied_through")
    for i in range(N):
        kind = kinds[i % len(kinds)]
        lo = rng.uniform(-3, 3, 2)
        size = np.array([logu(rng, 0.2, 5.0), logu(rng, 0.2, 5.0)])
        hi = lo + size
        cells = [int(rng.integers(1, 13)), int(rng.integers(1, 13))]
        if kind != "none":
            cells = [max(c, 2) for c in cells]
        if kind.startswith("crack"):
            cells = [max(c, 5) for c in cells]
        E, nu, rho = logu(rng, 1e6, 1e12), float(rng.uniform(0.0, 0.45)), float(rng.uniform(500, 9000))
        plane = "strain" if rng.random() < 0.5 else "stress"
        th = logu(rng, 0.005, 3.0) if rng.random() < 0.5 else None
        a = int(rng.integers(0, 2))              # load axis: 0 x, 1 y
        b = 1 - a
        s = logu(rng, 1e3, 1e8) * (1 if rng.random() < 0.7 else -1)
        edges = (("left", "right"), ("bottom", "top"))
        load_hi = rng.random() < 0.5             # load on the upper edge, hold the lower one
        fix_b_hi = rng.random() < 0.5
        load_edge = edges[a][1] if load_hi else edges[a][0]
        fix_a_edge = edges[a][0] if load_hi else edges[a][1]
        fix_b_edge = edges[b][1] if fix_b_hi else edges[b][0]
        a_fix = lo[a] if load_hi else hi[a]
        b_fix = hi[b] if fix_b_hi else lo[b]
        trac = [0.0, 0.0]
        trac[a] = s if load_hi else -s          # outward normal times s: tension for s > 0
        supports = [{"edge": fix_a_edge, "fix": ["xy"[a]]}, {"edge": fix_b_edge, "fix": ["xy"[b]]}]
        disc = []
        crack_pt = None
        if kind.startswith("crack"):
            # a line of constant b (parallel to the load), kept off the mesh lines
            cb = lo[b] + size[b] * (rng.uniform(0.65, 0.85) if "inclusion" in kind else rng.uniform(0.15, 0.85))
            if kind == "crack_tied_through":
                ends = (lo[a] - 0.1 * size[a], hi[a] + 0.1 * size[a])
            else:
                shape = rng.integers(0, 3)       # interior; through the held edge; through the loaded edge
                # at least 3 cells long: tips in cells that share no node
                # (a shorter crack is refused by this build, see the docs)
                span = min(0.75, max(0.1, 3.5 / cells[a]))
                p = rng.uniform(0.1, 0.9 - span)
                q = rng.uniform(p + span, 0.9)
                ends = [lo[a] + p * size[a], lo[a] + q * size[a]]
                if shape == 1:
                    ends[0 if load_hi else 1] = a_fix + (-0.05 if load_hi else 0.05) * size[a]
                elif shape == 2:
                    ends[1 if load_hi else 0] = (hi[a] + 0.05 * size[a]) if load_hi else (lo[a] - 0.05 * size[a])
            pts = []
            for ea in ends:
                pt = [0.0, 0.0]
                pt[a], pt[b] = float(ea), float(cb)
                pts.append(pt)
            faces = "tied" if "tied" in kind else ("unilateral" if "unilateral" in kind else "free")
            c = {"name": "c1", "type": "crack", "points": pts, "faces": faces}
            if faces != "free":
                h = size[b] / cells[b]
                kn = E / h * logu(rng, 1.0, 1e4)
                c["stiffness"] = [kn, kn * float(rng.uniform(0.2, 1.0))]
            disc.append(c)
            crack_pt = [0.0, 0.0]
            lo_a, hi_a = max(min(ends), lo[a]), min(max(ends), hi[a])
            crack_pt[a], crack_pt[b] = float(lo_a + rng.uniform(0.2, 0.8) * (hi_a - lo_a)), float(cb)
        if "inclusion" in kind:
            # one discontinuity per cell (a documented refusal): with a crack, keep
            # the circle 1.5 cells below the crack's line
            room = [size[0], size[1]]
            if crack_pt:
                room[b] = cb - 1.5 * size[b] / cells[b] - lo[b]
            rad = float(min(room) * rng.uniform(0.1, 0.35))
            cen = [float(lo[k] + rad + rng.uniform(0.05, 0.95) * (room[k] - 2 * rad)) for k in range(2)]
            disc.append({"name": "inc", "type": "inclusion", "circle": {"centre": cen, "radius": rad},
                         "material": {"youngs_modulus": E, "poisson_ratio": nu, "density": float(rng.uniform(500, 9000))}})
        eaa, ebb = elastic_strains(plane, E, nu, s)
        probes, ref = [], {}
        for j in range(3):
            p = [float(lo[k] + rng.uniform(0, 1) * size[k]) for k in range(2)]
            if j == 0:                           # a corner, on the loaded edge
                p = [float(hi[0] if (a == 0) == load_hi else lo[0]), float(hi[1])]
                p[a] = float(hi[a] if load_hi else lo[a])
            for comp in (0, 1):
                nm = f"u{j}{'xy'[comp]}"
                probes.append({"name": nm, "quantity": "displacement", "at": p, "component": comp})
                ref[nm] = (eaa * (p[a] - a_fix)) if comp == a else (ebb * (p[b] - b_fix))
        for j in range(2):
            p = [float(lo[k] + rng.uniform(0.02, 0.98) * size[k]) for k in range(2)]
            for comp in ("xx", "yy", "xy"):
                nm = f"s{j}{comp}"
                probes.append({"name": nm, "quantity": "stress", "at": p, "component": comp})
                ref[nm] = s if comp == "xy"[a] * 2 else 0.0
        probes.append({"name": "Ee", "quantity": "energy", "of": "elastic"})
        ref["Ee"] = 0.5 * s * eaa * size[0] * size[1] * (th or 1.0)
        if crack_pt:
            for comp in ("normal", "tangential"):
                nm = f"open_{comp}"
                probes.append({"name": nm, "quantity": "crack_opening", "crack": "c1", "at": crack_pt,
                               "component": comp})
                ref[nm] = 0.0
        cont = {"type": "plate", "plane": plane, "domain": {"min": [float(v) for v in lo], "max": [float(v) for v in hi]},
                "cells": cells, "material": {"youngs_modulus": E, "poisson_ratio": nu, "density": rho},
                "analysis": "static", "supports": supports,
                "loads": [{"edge": load_edge, "traction": trac, "shape": "step"}]}
        if th is not None:
            cont["thickness"] = th
        if disc:
            cont["discontinuities"] = disc
        name = f"tension{i:02d}_{plane}_{kind}"
        sc = {"name": name, "dimension": 2, "gravity": [0.0, -G], "continuum": cont, "output": {"probes": probes}}
        try:
            out = run(sc)
        except CliError as e:
            report(name + " runs", 1.0, 0.0, str(e))
            continue
        uscale = abs(eaa) * size[a] + abs(ebb) * size[b]
        err, worst = 0.0, ""
        for k_, v in ref.items():
            sc_ = uscale if k_[0] in "uo" else (abs(s) if k_[0] == "s" else abs(ref["Ee"]))
            e_ = abs(out[k_][0] - v) / sc_
            if e_ > err:
                err, worst = e_, f"{k_} {out[k_][0]:.6e} vs {v:.6e}"
        report(f"{name} uniform field", err, 1e-9, "closed form, round-off; worst " + worst, name)


# --------------------------------------------------------------------------
# 2. disk / sphere on an inclined plane (closed form)
# --------------------------------------------------------------------------
def cases_incline():
    rng = np.random.default_rng(2202)
    for i in range(N):
        dim = 2 if i % 3 else 3
        law = "hertz" if i % 4 == 1 else "linear"
        integ = INTEGRATORS[i % len(INTEGRATORS)]
        rolls = (i // 4) % 2 == 0
        m, r = logu(rng, 0.05, 20.0), logu(rng, 0.005, 0.5)
        kappa = 0.5 if dim == 2 else 0.4
        given = None
        if dim == 2 and rng.random() < 0.3:
            given = float(rng.uniform(0.2, 1.0))
            kappa = given
        mu = float(rng.uniform(0.05, 0.8))
        mur = float(rng.uniform(0.0, 0.4) * mu) if rng.random() < 0.5 else 0.0
        # rolls while friction can supply m g (kappa sin + mu_r cos)/(1+kappa)
        tan_c = ((1 + kappa) * mu - mur) / kappa
        tan_th = tan_c * (rng.uniform(0.3, 0.8) if rolls else rng.uniform(1.25, 2.5))
        tan_th = max(tan_th, 3 * mur)           # it must roll down at all
        th = math.atan(min(tan_th, math.tan(math.radians(75))))
        if (math.tan(th) <= tan_c) != rolls:
            rolls = math.tan(th) <= tan_c
        n = np.array([-math.sin(th), math.cos(th)])
        tvec = np.array([math.cos(th), math.sin(th)])
        wn = logu(rng, 300.0, 3000.0)            # normal contact frequency
        S = m * wn * wn
        F = m * G * math.cos(th)
        part = {"name": "d", "mass": m, "radius": r}
        contact = {"law": law, "friction": mu, "rolling_friction": mur}
        plane = {"point": [0.0] * dim, "normal": list(n) + ([0.0] if dim == 3 else [])}
        if law == "linear":
            part["stiffness"] = S
            d0 = F / S
            contact["damping_ratio"] = float(rng.uniform(0.2, 0.7))
            contact["tangential_stiffness_ratio"] = float(rng.uniform(0.3, 1.0))
        else:
            d0 = 1.5 * F / S                     # F = 2/3 S d for Hertz
            estar = S / (2 * math.sqrt(r * d0))
            nu = float(rng.uniform(0.15, 0.45))
            if rng.random() < 0.5:
                part.update({"youngs_modulus": estar * (1 - nu * nu), "poisson_ratio": nu})
            else:                                # same material for the wall: half each
                part.update({"youngs_modulus": 2 * estar * (1 - nu * nu), "poisson_ratio": nu})
                plane.update({"youngs_modulus": 2 * estar * (1 - nu * nu), "poisson_ratio": nu})
            contact["restitution"] = float(rng.uniform(0.2, 0.7))
        if mur == 0.0:
            del contact["rolling_friction"]
        p0 = (r - d0) * n
        part["position"] = [float(v) for v in p0] + ([0.0] if dim == 3 else [])
        part["velocity"] = [0.0] * dim
        part["angular_velocity"] = 0.0 if dim == 2 else [0.0, 0.0, 0.0]
        if given:
            part["inertia"] = given * m * r * r
        w_t = wn * math.sqrt(1 + 1 / kappa)      # tangential spring with rotation: the fastest mode
        dt = 0.03 / w_t
        end = 0.3
        every = dt * max(1, round(0.01 / dt))
        end = every * round(end / every)
        probes = [{"name": f"v{c}", "particle": "d", "quantity": "velocity", "component": c} for c in (0, 1)]
        probes.append({"name": "w", "particle": "d", "quantity": "angular_velocity"} if dim == 2 else
                      {"name": "w", "particle": "d", "quantity": "angular_velocity", "component": 2})
        name = f"incline{i:02d}_{dim}d_{law}_{integ}_{'rolls' if rolls else 'slides'}"
        sc = {"name": name, "dimension": dim, "gravity": [0.0, -G] + ([0.0] if dim == 3 else []),
              "time": {"end": end, "dt": dt},
              "dem": {"integrator": integ, "contact": contact, "particles": [part], "planes": [plane]},
              "output": {"every": every, "probes": probes}}
        try:
            out = run(sc)
        except CliError as e:
            report(name + " runs", 1.0, 0.0, str(e))
            continue
        t = out["t"][-1]
        vs = out["v0"][-1] * tvec[0] + out["v1"][-1] * tvec[1]
        if rolls:
            acc = -G * (math.sin(th) - mur * math.cos(th)) / (1 + kappa)
            alpha = -acc / r
        else:
            acc = -G * (math.sin(th) - mu * math.cos(th))
            alpha = (mu - mur) * G * math.cos(th) / (kappa * r)
        why = "closed form; spring transients ~ 1 %"
        report(f"{name} v", abs(vs - acc * t) / abs(acc * t), 0.01, why, name)
        report(f"{name} omega", abs(out["w"][-1] - alpha * t) / abs(alpha * t), 0.01, why, name)
        if rolls:
            report(f"{name} omega r = -v", abs(out["w"][-1] * r + vs) / abs(vs), 0.01, "rolling without slip", name)


# --------------------------------------------------------------------------
# 3. a disk at rest on a supported plate (static CLI run of the plate)
# --------------------------------------------------------------------------
def cases_rest():
    rng = np.random.default_rng(2303)
    nrest = max(4, N // 2)
    for i in range(nrest):
        law = "hertz" if i % 3 == 2 else "linear"
        integ = INTEGRATORS[i % 4]           # abm4_events is refused against the plate
        lo = rng.uniform(-2, 2, 2)
        Lx, Ly = logu(rng, 0.5, 3.0), logu(rng, 0.2, 1.0)
        hi = lo + np.array([Lx, Ly])
        nx, ny = int(rng.integers(2, 11)), int(rng.integers(1, 7))
        E, nu, rho = logu(rng, 1e7, 1e9), float(rng.uniform(0.0, 0.45)), float(rng.uniform(1000, 8000))
        plane = "strain" if rng.random() < 0.5 else "stress"
        th = logu(rng, 0.05, 2.0) if plane == "stress" else None
        on_node = i % 2 == 0
        if on_node:
            xc = float(lo[0] + int(rng.integers(1, nx)) * (Lx / nx))
        else:
            xc = float(lo[0] + rng.uniform(0.1, 0.9) * Lx)
        top = float(hi[1])
        tk = th or 1.0
        m_node = rho * tk * (Lx / nx) * (Ly / ny) / 4   # a top node's lumped mass, at least
        m, r = m_node * logu(rng, 0.5, 20.0), float(Lx * rng.uniform(0.02, 0.1))
        c = math.sqrt(E / rho)
        w1 = 0.5 * math.pi * c / Ly             # the plate's lowest mode, about
        w_ex = w1 * logu(rng, 0.3, 1.0)          # the disk-node exchange, sqrt(k (1/m_node + 1/m))
        S = w_ex * w_ex / (1 / m_node + 1 / m)
        W = m * G
        part = {"name": "d", "mass": m, "radius": r}
        contact = {"law": law}
        if law == "linear":
            part["stiffness"] = S
            d0 = W / S
            contact["damping_ratio"] = float(rng.uniform(0.4, 0.9))
        else:
            d0 = 1.5 * W / S                     # F = 2/3 S d for Hertz
            estar = S / (2 * math.sqrt(r * d0))
            pnu = float(rng.uniform(0.15, 0.45))
            plate_part = (1 - nu * nu) / E       # the plate's material is the second body
            inv_p = 1 / estar - plate_part
            if inv_p <= 0:                        # the plate alone is softer: a stiff disk
                inv_p = 0.01 * plate_part
            part.update({"youngs_modulus": (1 - pnu * pnu) / inv_p, "poisson_ratio": pnu})
            estar = 1 / (inv_p + plate_part)
            d0 = (0.75 * W / (estar * math.sqrt(r))) ** (2 / 3)
            if d0 > 0.2 * r:                      # a soft plate: a larger disk keeps its centre out
                r = 5 * d0
                d0 = (0.75 * W / (estar * math.sqrt(r))) ** (2 / 3)
            S = 2 * estar * math.sqrt(r * d0)
            contact["restitution"] = float(rng.uniform(0.05, 0.3))
        # The deflected top slopes under the disk (even over a node: the plate
        # bends and moves sideways under the load, no plate here is symmetric):
        # a frictionless disk creeps down it and a free-rolling one rolls, both
        # further as the plate bends more, so friction and rolling friction hold it.
        contact["friction"] = float(rng.uniform(0.1, 0.8))
        if law == "linear":
            contact["tangential_stiffness_ratio"] = float(rng.uniform(0.3, 1.0))
        contact["rolling_friction"] = float(rng.uniform(0.01, 0.1))
        gam = float(rng.uniform(0.6, 0.75))
        beta = (gam + 0.5) ** 2 / 4
        w_ex = math.sqrt(1.5 * S * (1 / m_node + 1 / m))   # the CLI refuses omega dt > 1
        wc = math.sqrt(S / m)
        dt = min(1.5 / w1, 0.6 / w_ex)
        subs = int(math.ceil(wc * 2.5 * dt / 0.04))
        zeta_min = contact.get("damping_ratio", 0.3)
        steps = int(100 * math.ceil(max(3000, 60 / (zeta_min * wc * dt)) / 100))
        every = 100 * dt
        end = steps * dt
        supports = [{"edge": "bottom", "fix": ["x", "y"]}]
        if rng.random() < 0.4:
            supports.append({"edge": "left", "fix": ["x"]})
        cont = {"type": "plate", "plane": plane, "domain": {"min": [float(v) for v in lo], "max": [float(v) for v in hi]},
                "cells": [nx, ny], "material": {"youngs_modulus": E, "poisson_ratio": nu, "density": rho},
                "analysis": "dynamic", "newmark": {"beta": beta, "gamma": gam}, "supports": supports}
        if th is not None:
            cont["thickness"] = th
        part.update({"radius": r, "position": [xc, top + r - d0], "velocity": [0.0, 0.0], "angular_velocity": 0.0})
        name = f"rest{i:02d}_{law}_{integ}" + ("_on_node" if on_node else "")
        probes = [{"name": "F", "quantity": "contact_force", "between": ["d", "plate"], "part": "normal"},
                  {"name": "Ft", "quantity": "contact_force", "between": ["d", "plate"], "part": "tangential"},
                  {"name": "y", "particle": "d", "quantity": "position", "component": 1},
                  {"name": "x", "particle": "d", "quantity": "position", "component": 0},
                  {"name": "uy", "quantity": "displacement", "at": [xc, top], "component": 1},
                  {"name": "ux", "quantity": "displacement", "at": [xc, top], "component": 0},
                  {"name": "vx", "particle": "d", "quantity": "velocity", "component": 0},
                  {"name": "w", "particle": "d", "quantity": "angular_velocity"}]
        sc = {"name": name, "dimension": 2, "gravity": [0.0, -G],
              "time": {"end": end, "dt": dt, "dem_substeps": subs},
              "dem": {"integrator": integ, "contact": contact, "particles": [part]},
              "continuum": cont, "output": {"every": every, "probes": probes}}
        try:
            try:
                out = run(sc)
            except CliError as e:
                # The CLI refuses a step too long for the disk-node exchange and
                # names its omega (a lumped node mass this script only estimates):
                # take 0.6 / omega, as the script meant to.
                mt = re.search(r"= ([0-9.e+-]+) rad/s", str(e))
                if not mt or "too long for the disk-plate exchange" not in str(e):
                    raise
                dt = 0.6 / float(mt.group(1))
                subs = int(math.ceil(wc * 2.5 * dt / 0.04))
                steps = int(100 * math.ceil(max(3000, 60 / (zeta_min * wc * dt)) / 100))
                sc["time"] = {"end": steps * dt, "dt": dt, "dem_substeps": subs}
                sc["output"]["every"] = 100 * dt
                out = run(sc)
        except CliError as e:
            # is it the friction? the same scene without it, printed only
            bare = json.loads(json.dumps(sc))
            for k_ in ("friction", "rolling_friction", "tangential_stiffness_ratio"):
                bare["dem"]["contact"].pop(k_, None)
            try:
                run(bare, name=name + "_frictionless")
                also = "; without friction it runs"
            except CliError as e2:
                also = "; without friction: " + str(e2).split(": ", 1)[1][:120]
            report(name + " runs", 1.0, 0.0, str(e) + also)
            continue
        SCENES_COUPLED.append(sc)
        Fn, Ft = out["F"][-1], out["Ft"][-1]
        drift_F = abs(out["F"][-1] - out["F"][-2]) / W
        # The disk at rest: gravity and the contact force balance, so the force
        # is m g however the contact normal tilts (the kernel finds the contact
        # on the deformed boundary, which slopes under the load: a frictional
        # disk then holds a tangential part m g sin(phi), a frictionless one
        # slides to where the slope is zero).
        report(f"{name} |contact_force| = m g", abs(math.hypot(Fn, Ft) - W) / W, 1e-6,
               f"disk's equilibrium, settled (last 100 steps moved F by {drift_F:.1e} m g)", name)
        # Where the disk presses: the boundary point under its centre, in the
        # plate's reference coordinates X = x_disk - u_x (u_x at xc; the static
        # run below gives u_x at X too, and the difference is allowed for).
        X = float(out["x"][-1] - out["ux"][-1])
        hx = Lx / nx
        dx = 1e-3 * hx
        st = json.loads(json.dumps(cont))
        st["analysis"] = "static"
        del st["newmark"]
        st["loads"] = [{"at": [X, top], "force": [0.0, -W], "shape": "step"}]
        sprobes = [{"name": "uyc", "quantity": "displacement", "at": [xc, top], "component": 1},
                   {"name": "uyX", "quantity": "displacement", "at": [X, top], "component": 1},
                   {"name": "uyl", "quantity": "displacement", "at": [X - dx, top], "component": 1},
                   {"name": "uyr", "quantity": "displacement", "at": [X + dx, top], "component": 1},
                   {"name": "uxc", "quantity": "displacement", "at": [xc, top], "component": 0},
                   {"name": "uxX", "quantity": "displacement", "at": [X, top], "component": 0}]
        ssc = {"name": name + "_static", "dimension": 2, "gravity": [0.0, -G], "continuum": st,
               "output": {"probes": sprobes}}
        try:
            ref = run(ssc)
        except CliError as e:
            report(name + "_static runs", 1.0, 0.0, str(e))
            continue
        # Tolerance: the true contact point is off X by the tilt of the normal,
        # at most r phi with phi the larger of the deflection's slope there and
        # |F_t| / |F| (over a node the deformed boundary has a kink, and the
        # closest boundary points of a disk above it lie on the two edges, r phi
        # either side of the node), and by u_x(X) - u_x(xc). Moving the load by d changes the deflection at a fixed
        # point by at most (steepest slope) x d; the slope is taken over 1e-3 of a
        # cell either side of the load (the deflection's steepest place), doubled
        # for its variation over d. Plus 1e-6 of the deflection for what the
        # damped run has not yet settled (its last 100 steps moved it far less).
        uyX = ref["uyX"][0]
        slope = max(abs(ref["uyl"][0] - uyX), abs(ref["uyr"][0] - uyX)) / dx
        d = r * max(abs(Ft) / W, slope) + abs(ref["uxX"][0] - ref["uxc"][0])
        tol = 2 * slope * d + 1e-6 * abs(uyX)
        drift_u = abs(out["uy"][-1] - out["uy"][-2])
        report(f"{name} at rest", drift_u / abs(uyX), 1e-7,
               f"u_y(xc) moved over the last 100 steps, / |u|; disk v_x {out['vx'][-1]:.1e} m/s, "
               f"omega r {out['w'][-1] * r:.1e} m/s, |F_t| / (mu F_n) {abs(Ft) / (contact['friction'] * Fn):.1e}",
               name)
        report(f"{name} u_y(xc) = static", abs(out["uy"][-1] - ref["uyc"][0]), tol,
               f"static CLI run, load at X = xc {X - xc:+.1e} m; 2 slope d (d {d:.1e} m) + 1e-6 |u| "
               f"(drift {drift_u:.1e} m)", name)
        if law == "linear":
            dstat = W / S
        else:
            dstat = d0
        yref = top + uyX + r - dstat
        report(f"{name} disk height", abs(out["y"][-1] - yref), tol + 1e-6 * dstat + r * (Ft / W) ** 2,
               "top + u_y(static, X) + r - the law's static overlap", name)


# --------------------------------------------------------------------------
# 4. a free plate with a void and a crack hit by disks
# --------------------------------------------------------------------------
SCENES_COUPLED = []


def cases_free():
    rng = np.random.default_rng(2404)
    nfree = max(4, N // 2)
    for i in range(nfree):
        conservative = i % 2 == 1            # no damping, no friction: energy must not rise
        law = "hertz" if i % 3 == 2 else "linear"
        integ = INTEGRATORS[i % 4]           # abm4_events is refused against the plate
        lo = rng.uniform(-2, 2, 2)
        Lx, Ly = logu(rng, 0.5, 2.0), logu(rng, 0.3, 1.0)
        hi = lo + np.array([Lx, Ly])
        nx, ny = int(rng.integers(3, 11)), int(rng.integers(7, 11))
        E, nu, rho = logu(rng, 1e7, 1e9), float(rng.uniform(0.0, 0.45)), float(rng.uniform(500, 3000))
        plane = "strain" if rng.random() < 0.5 else "stress"
        # a void in the left half, a crack in the right half (through the top edge or inside)
        vc = [float(lo[0] + Lx * rng.uniform(0.2, 0.35)), float(lo[1] + Ly * rng.uniform(0.35, 0.65))]
        vr = float(min(Lx, Ly) * rng.uniform(0.08, 0.18))
        if rng.random() < 0.5:
            void = {"name": "hole", "type": "void", "circle": {"centre": vc, "radius": vr}}
        else:
            ang = np.sort(rng.uniform(0, 2 * math.pi, 5))
            poly = [[vc[0] + vr * math.cos(a_), vc[1] + vr * math.sin(a_)] for a_ in ang]
            void = {"name": "hole", "type": "void", "polygon": poly}
        cx0 = float(lo[0] + Lx * rng.uniform(0.6, 0.8))
        # tips over 3.5 cells apart (closer ones are refused, see the docs)
        p1 = [cx0, float(lo[1] + Ly * rng.uniform(0.1, 0.2))]
        p2 = [cx0 + float(Lx * rng.uniform(-0.1, 0.1)),
              float(hi[1] + 0.1 * Ly) if rng.random() < 0.5 else float(lo[1] + Ly * rng.uniform(0.75, 0.9))]
        crack = {"name": "c1", "type": "crack", "points": [p1, p2], "faces": "free"}
        cont = {"type": "plate", "plane": plane, "domain": {"min": [float(v) for v in lo], "max": [float(v) for v in hi]},
                "cells": [nx, ny], "material": {"youngs_modulus": E, "poisson_ratio": nu, "density": rho},
                "analysis": "dynamic", "discontinuities": [void, crack]}
        if not conservative or rng.random() < 0.5:
            gam = 0.5 if conservative else float(rng.uniform(0.5, 0.7))
            cont["newmark"] = {"beta": (gam + 0.5) ** 2 / 4, "gamma": gam}
        c = math.sqrt(E / rho)
        parts, wmax = [], 0.0
        nd = int(rng.integers(3, 5))
        sides = rng.permutation(4)[:nd]
        for j, side in enumerate(sides):
            m, r = logu(rng, 0.2, 5.0), float(min(Lx, Ly) * rng.uniform(0.03, 0.08))
            sp = float(rng.uniform(0.5, 3.0))
            gap = float(rng.uniform(0.1, 0.5)) * r
            f = float(rng.uniform(0.15, 0.85))
            if side == 0:
                pos, vel = [lo[0] - r - gap, lo[1] + f * Ly], [sp, float(rng.uniform(-0.5, 0.5))]
            elif side == 1:
                pos, vel = [hi[0] + r + gap, lo[1] + f * Ly], [-sp, float(rng.uniform(-0.5, 0.5))]
            elif side == 2:
                pos, vel = [lo[0] + f * Lx, lo[1] - r - gap], [float(rng.uniform(-0.5, 0.5)), sp]
            else:
                pos, vel = [lo[0] + f * Lx, hi[1] + r + gap], [float(rng.uniform(-0.5, 0.5)), -sp]
            wc = logu(rng, 300.0, 2000.0)
            p = {"name": f"d{j}", "mass": m, "radius": r, "position": [float(v) for v in pos],
                 "velocity": vel, "angular_velocity": float(rng.uniform(-20, 20))}
            if law == "linear":
                p["stiffness"] = m * wc * wc
            else:
                p.update({"youngs_modulus": logu(rng, 1e8, 1e10), "poisson_ratio": float(rng.uniform(0.2, 0.4))})
                # Hertz against this plate at the closing speed: the peak stiffness's frequency
                es = 1 / ((1 - p["poisson_ratio"] ** 2) / p["youngs_modulus"] + (1 - nu * nu) / E)
                dmax = (15 * m * sp * sp / (16 * es * math.sqrt(r))) ** 0.4
                wc = math.sqrt(2 * es * math.sqrt(r * dmax) / m)
            wmax = max(wmax, wc)
            parts.append(p)
        contact = {"law": law}
        if law == "linear":
            contact["damping_ratio"] = 0.0 if conservative else float(rng.uniform(0.05, 0.5))
        else:
            contact["restitution"] = 1.0 if conservative else float(rng.uniform(0.3, 0.9))
        if not conservative:
            contact["friction"] = float(rng.uniform(0.2, 0.8))
            if law == "linear":
                contact["tangential_stiffness_ratio"] = float(rng.uniform(0.3, 1.0))
            if rng.random() < 0.5:
                contact["rolling_friction"] = float(rng.uniform(0.01, 0.2))
        dt = min(0.2 * (Lx / nx) / c, 2e-4)
        subs = int(math.ceil(wmax * 2.0 * dt / 0.04))
        steps = 400
        end = steps * dt
        name = f"free{i:02d}_{law}_{integ}" + ("_conservative" if conservative else "_frictional")
        probes = [{"name": f"p{k}", "quantity": "momentum", "of": "total", "component": k} for k in (0, 1)]
        probes.append({"name": "E", "quantity": "energy", "of": "total"})
        probes += [{"name": f"f{j}", "quantity": "contact_force", "between": [p["name"], "plate"]}
                   for j, p in enumerate(parts)]
        sc = {"name": name, "dimension": 2, "gravity": [0.0, 0.0],
              "time": {"end": end, "dt": dt, "dem_substeps": subs},
              "dem": {"integrator": integ, "contact": contact, "particles": parts},
              "continuum": cont, "output": {"every": dt, "probes": probes}}
        try:
            out = run(sc)
        except CliError as e:
            report(name + " runs", 1.0, 0.0, str(e))
            continue
        SCENES_COUPLED.append(sc)
        hits = sum(int(np.any(out[f"f{j}"] > 0)) for j in range(len(parts)))
        scale = sum(p["mass"] * math.hypot(*p["velocity"]) for p in parts)
        # round-off: each step adds forces of size ~ scale / dt, each to ~eps; a sum of
        # nodes x steps x substeps rounded terms: 1e3 eps per step is generous round-off
        # and far below any real imbalance (a force missed for one substep is ~ scale / subs)
        nsteps = steps * subs
        mom_tol = 1e3 * EPS * scale * math.sqrt(nsteps) * 10
        err = max(float(np.max(np.abs(out[f"p{k}"] - out[f"p{k}"][0]))) for k in (0, 1))
        report(f"{name} momentum ({hits}/{len(parts)} hit)", err, mom_tol,
               f"round-off of sum m|v| = {scale:.2e}", name)
        if conservative:
            E0 = out["E"][0]
            rise = float(np.max(out["E"] - E0))
            touching = np.any(np.vstack([out[f"f{j}"] for j in range(len(parts))]) != 0, axis=0)
            k = int(np.argmax(out["E"]))
            tol_e = 1e3 * EPS * math.sqrt(nsteps)
            report(f"{name} energy never rises", max(rise, 0.0) / E0, tol_e,
                   f"no damping, no friction; largest at row {k} ({'in' if touching[k] else 'out of'} contact)", name)
            # after the last contact the disks fly free and Newmark (1/4, 1/2) keeps
            # the plate's energy: what is left is what the contacts gave or took
            if not touching[-1] and np.any(touching):
                last = int(np.nonzero(touching)[0][-1]) + 1
                net = float(np.max(out["E"][last:] - E0))
                report(f"{name} energy after the contacts <= E0", max(net, 0.0) / E0, tol_e,
                       f"contacts over at row {last}; E_end/E0 - 1 = {out['E'][-1] / E0 - 1:.2e}", name)


# --------------------------------------------------------------------------
# 5. --threads 1 vs 2
# --------------------------------------------------------------------------
def cases_threads():
    if not SCENES_COUPLED:
        cases_rest()
        cases_free()
    pick = SCENES_COUPLED[:: max(1, len(SCENES_COUPLED) // 6)][:6]
    for sc in pick:
        texts = []
        try:
            for th in (1, 2):
                run(sc, name=f"{sc['name']}_t{th}", threads=th)
                texts.append(open(os.path.join(TMP, f"{sc['name']}_t{th}.csv"), "rb").read())
        except CliError as e:
            report(sc["name"] + " --threads runs", 1.0, 0.0, str(e))
            continue
        report(f"{sc['name']} --threads 1 vs 2", float(texts[0] != texts[1]), 0.0,
               "same CSV bytes on any worker count", sc["name"] + "_t2")


CASES = {"tension": cases_tension, "incline": cases_incline, "rest": cases_rest, "free": cases_free,
         "threads": cases_threads}


def main():
    global CLI, TMP, KEEP, N
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=CLI)
    ap.add_argument("-k", default="")
    ap.add_argument("-n", type=int, default=N, help="variants per case (rest and free: half)")
    ap.add_argument("--keep", default=None, help="directory for the scenes of failed checks")
    a = ap.parse_args()
    CLI, N = a.cli, a.n
    KEEP = a.keep
    with tempfile.TemporaryDirectory() as d:
        TMP = d
        failed_run = False
        for key, fn in CASES.items():
            if a.k and a.k not in key:
                continue
            try:
                fn()
            except CliError as e:
                print(f"FAIL {key}: {e}", flush=True)
                failed_run = True
    # per case and check kind: how many, how many failed, the largest error
    groups = {}
    for case, err, tol, good, _ in RESULTS:
        key = (re.sub(r"\d.*", "", case.split()[0]), case.split(" ", 1)[1] if " " in case else "")
        key = (key[0], re.sub(r"\(\d+/\d+ hit\)", "", key[1]).strip())
        g = groups.setdefault(key, [0, 0, 0.0, 0.0])
        g[0] += 1
        g[1] += not good
        if good:
            g[2] = max(g[2], err)
        else:
            g[3] = max(g[3], err)
    print(f"\n{'case':8s} {'check':34s} {'runs':>5s} {'failed':>6s} {'largest ok':>10s} {'largest fail':>12s}")
    for (c, k), g in groups.items():
        print(f"{c:8s} {k[:34]:34s} {g[0]:5d} {g[1]:6d} {g[2]:10.2e} {g[3]:12.2e}")
    ok = sum(r[3] for r in RESULTS)
    print(f"{ok} of {len(RESULTS)} checks within tolerance")
    if ok < len(RESULTS):
        print(f"scenes of failed checks kept in {KEEP}")
    if failed_run or any(r[1] == 1.0 and r[2] == 0.0 and r[0].endswith("runs") for r in RESULTS):
        return 2
    return 0 if all(r[3] for r in RESULTS) else 1


if __name__ == "__main__":
    sys.exit(main())
