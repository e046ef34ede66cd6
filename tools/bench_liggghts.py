#!/usr/bin/python3
"""The dense settled packing, xfdem against LIGGGHTS, side by side.

    /usr/bin/python3 tools/bench_liggghts.py [--sizes 10000 60000] [--steps 1000]
                                             [--repetitions 3] [--build build/release]
                                             [--instructions 10000] [--friction] [--hertz]

For each size N:
  1. xfdem_packing_export writes the packing of the packing benchmarks
     (bench/dem_packing.hpp: N spheres r = 1 mm, 2500 kg/m^3, k = 2000 N/m,
     zeta = 0.1, settled under gravity in a box of six planes) and the state
     after --steps steps from rest, and checks that one and two workers end
     with the same bits.
  2. The same spheres go into a LIGGGHTS data file and input script, which
     runs --steps steps at the same dt on 2 MPI ranks (mpirun -np 2); its
     "Loop time" gives ns per particle-step, its timing breakdown
     (Pair / Neigh / Comm / Outpt / Other) where its time goes.
  3. xfdem_bench runs BM_DemPacking/vs_liggghts/N (verlet, 1 and 2 workers;
     Google Benchmark, median of --repetitions); its counters give ns per
     particle-step and the kernel's stage profile (broad phase, contacts,
     integration).
  4. With --instructions N: instructions per particle-step of both codes on
     one core under callgrind (a figure the machine's load does not change).
  5. Same physics: the two codes' states after --steps steps are compared
     (kinetic energy, mean overlap of touching pairs, largest position
     difference against the largest displacement).

The equivalent of the kernel's linear law in LIGGGHTS is
`model hooke/stiffness tangential no_history` with `absolute_damping on`:
F_n = k_n delta - gamma_n v_n with k_n and gamma_n given per type pair, no
force limit (limitForce off: the dashpot may pull, as the kernel's `linear`
law), coefficientFriction 0 and k_t = gamma_t = 0 (no tangential force).
k_n is the kernel's series stiffness (k/2 for a pair, k for a wall) and
gamma_n its eta = 2 zeta sqrt(K m_eff). `model hooke` would derive k_n from
Young's modulus and an impact velocity, and `hertz` is another law. The
integrator (nve/sphere) is velocity Verlet whose dashpot sees the half-step
velocity, as the kernel's `verlet`.

Friction (--friction, when the kernel has DemDesc::friction): mu = 0.5,
k_t = 2/7 k_n, against `model hooke/stiffness tangential history` (the same
Cundall-Strack spring: k_t given per type pair, capped at mu |F_n| and reset
to the cap when sliding, dashpot gamma_t = 2 zeta sqrt(k_t m_eff) while
sticking).

Hertz-Mindlin (--hertz, when the kernel has the hertz law): E = 5e7 Pa,
nu = 0.25 (spheres and walls), restitution 0.7, mu = 0.5, against `model
hertz tangential history` with youngsModulus, poissonsRatio,
coefficientRestitution and coefficientFriction set to the same values (the
same normal law and damping; the tangential history differs by design: the
kernel keeps it as a force, LIGGGHTS 3.8 as a displacement times the current
S_t, docs/dem.md).

Nothing is installed: if `liggghts` or `mpirun` is missing, the script says
what to apt-get and stops.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fail(message, code=2):
    print("bench_liggghts: " + message, file=sys.stderr)
    sys.exit(code)


def read_packing(path):
    meta, rows = {}, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                key, value = line[1:].split()
                meta[key] = float(value)
            else:
                rows.append([float(t) for t in line.split()])
    return meta, np.array(rows)


def write_liggghts(directory, meta, x, steps):
    """Data file and input script for the packing; returns the input's path."""
    r, side, top = meta["radius"], meta["side"], meta["top"]
    margin = 2 * r  # the box holds the walls; particles never reach its faces
    with open(os.path.join(directory, "packing.data"), "w") as f:
        f.write("xfdem dense packing\n\n%d atoms\n2 atom types\n\n" % len(x))
        f.write("%r %r xlo xhi\n%r %r ylo yhi\n%r %r zlo zhi\n\nAtoms\n\n"
                % (-margin, side + margin, -margin, side + margin, -margin, top + margin))
        for i, p in enumerate(x):
            f.write("%d 1 %r %r %r %r %r\n" % (i + 1, 2 * r, meta["density"], p[0], p[1], p[2]))
    kp, kw = meta["pair_stiffness"], meta["plane_stiffness"]
    ep, ew = meta["pair_eta"], meta["plane_eta"]
    mu = meta.get("friction", 0.0)
    hertz = meta.get("law_hertz", 0.0) > 0
    if hertz:
        model = "model hertz tangential history"
    elif mu > 0:
        # Cundall-Strack spring k_t = ratio k_n, capped at mu |F_n| (reset to
        # the cap when sliding), dashpot 2 zeta sqrt(k_t m_eff) while sticking.
        ratio, zeta, m = meta["tangential_ratio"], meta["damping_ratio"], meta["mass"]
        ktp, ktw = ratio * kp, ratio * kw
        etp, etw = 2 * zeta * math.sqrt(ktp * 0.5 * m), 2 * zeta * math.sqrt(ktw * m)
        model = "model hooke/stiffness tangential history"
    else:
        ktp = ktw = etp = etw = 0.0
        model = "model hooke/stiffness tangential no_history"
    walls = [("xplane", 0.0), ("xplane", side), ("yplane", 0.0), ("yplane", side), ("zplane", 0.0), ("zplane", top)]
    lines = [
        "atom_style granular",
        "atom_modify map array",
        "boundary f f f",
        "newton off",
        "communicate single vel yes",
        "units si",
        "read_data packing.data",
        # skin: half a radius, the kernel's default; rebuilt when a particle
        # has moved half of it (LIGGGHTS checks every step).
        "neighbor %r bin" % (0.5 * r),
        "neigh_modify delay 0",
        # type 1: the spheres; type 2: the walls
    ]
    if hertz:
        E, nu, e = meta["youngs_modulus"], meta["poisson_ratio"], meta["restitution"]
        lines += [
            "fix m1 all property/global youngsModulus peratomtype %r %r" % (E, E),
            "fix m2 all property/global poissonsRatio peratomtype %r %r" % (nu, nu),
            "fix m3 all property/global coefficientRestitution peratomtypepair 2 %r %r %r %r" % (e, e, e, e),
            "fix m4 all property/global coefficientFriction peratomtypepair 2 %r %r %r %r" % (mu, mu, mu, mu),
            "pair_style gran %s" % model,
        ]
        wall_options = ""
    else:
        lines += [
            "fix m1 all property/global kn peratomtypepair 2 %r %r %r %r" % (kp, kw, kw, kw),
            "fix m2 all property/global kt peratomtypepair 2 %r %r %r %r" % (ktp, ktw, ktw, ktw),
            "fix m3 all property/global gamman_abs peratomtypepair 2 %r %r %r %r" % (ep, ew, ew, ew),
            "fix m4 all property/global gammat_abs peratomtypepair 2 %r %r %r %r" % (etp, etw, etw, etw),
            "fix m5 all property/global coefficientFriction peratomtypepair 2 %r %r %r %r" % (mu, mu, mu, mu),
            "pair_style gran %s absolute_damping on" % model,
        ]
        wall_options = " absolute_damping on"
    lines += [
        "pair_coeff * *",
        "timestep %r" % meta["dt"],
        "fix gravity all gravity %r vector 0.0 0.0 -1.0" % -meta["gravity"],
    ]
    for k, (kind, at) in enumerate(walls):
        lines.append("fix wall%d all wall/gran %s primitive type 2 %s %r%s" % (k, model, kind, at, wall_options))
    lines += [
        "fix integrate all nve/sphere",
        "thermo_style custom step atoms ke",
        "thermo %d" % steps,
        "dump after all custom %d after.dump id x y z vx vy vz" % steps,
        "dump_modify after sort id",
        "run %d" % steps,
    ]
    path = os.path.join(directory, "in.packing")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def run_liggghts(directory, ranks, mpirun_extra):
    cmd = ["mpirun"] + mpirun_extra + ["-np", str(ranks), "liggghts", "-in", "in.packing", "-echo", "none",
                                        "-log", "log.liggghts"]
    done = subprocess.run(cmd, cwd=directory, capture_output=True, text=True)
    if done.returncode != 0:
        fail("LIGGGHTS failed (%s):\n%s%s" % (" ".join(cmd), done.stdout[-3000:], done.stderr[-3000:]), 1)
    log = done.stdout
    loop = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    if not loop:
        fail("no 'Loop time' in LIGGGHTS's output:\n" + log[-3000:], 1)
    stages = {}
    for name, seconds in re.findall(r"^(\w+)\s+time \(%\) = ([0-9.eE+-]+)", log, re.M):
        stages[name] = float(seconds)
    builds = re.search(r"Neighbor list builds = (\d+)", log)
    return {"loop_s": float(loop.group(1)), "procs": int(loop.group(2)), "steps": int(loop.group(3)),
            "atoms": int(loop.group(4)), "stages": stages, "builds": int(builds.group(1)) if builds else -1,
            "command": " ".join(cmd)}


def read_dump_last(path, n):
    with open(path) as f:
        lines = f.readlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    rows = np.array([[float(t) for t in line.split()] for line in lines[start + 1:start + 1 + n]])
    rows = rows[np.argsort(rows[:, 0])]
    return rows[:, 1:4], rows[:, 4:7]


def mean_overlap(x, r):
    """Mean overlap of touching pairs (over pairs) and touching pairs per particle."""
    try:
        from scipy.spatial import cKDTree
    except ImportError:
        return float("nan"), float("nan")
    pairs = cKDTree(x).query_pairs(2 * r, output_type="ndarray")
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    overlap = 2 * r - d
    return float(overlap.mean()), 2.0 * len(pairs) / len(x)


def callgrind_refs(cmd, cwd):
    """Instructions executed by cmd under callgrind (its 'I refs' total)."""
    done = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null"] + cmd, cwd=cwd,
                          capture_output=True, text=True)
    found = re.search(r"I\s+refs:\s+([0-9,]+)", done.stderr)
    if done.returncode != 0 or not found:
        fail("callgrind failed on %s:\n%s" % (" ".join(cmd), done.stderr[-3000:]), 1)
    return int(found.group(1).replace(",", ""))


EXPORT_OPTION = {"frictionless": [], "friction": ["friction"], "hertz": ["hertz"]}
BENCH_ROW = {"frictionless": "vs_liggghts", "friction": "vs_liggghts_friction", "hertz": "vs_liggghts_hertz"}


def instructions(n, law, export, directory, meta, x0):
    """Instructions per particle-step on one core (LIGGGHTS 1 rank, xfdem 1
    worker), from the difference of a 60- and a 10-step run under callgrind,
    so that reading, setup and the packing's generation cancel: a count the
    machine's load does not change."""
    lo, hi = 10, 60
    counts = {}
    for steps in (lo, hi):
        write_liggghts(directory, meta, x0, steps)
        lig = callgrind_refs(["liggghts", "-in", "in.packing", "-echo", "none", "-log", "none", "-screen", "none"],
                             directory)
        ours_dir = os.path.join(directory, "ir_%d" % steps)
        os.makedirs(ours_dir, exist_ok=True)
        ours = callgrind_refs([export, str(n), str(steps), ours_dir, "one_worker"] + EXPORT_OPTION[law], directory)
        counts[steps] = (lig, ours)
    per = 1.0 / ((hi - lo) * n)
    return {"lig": (counts[hi][0] - counts[lo][0]) * per, "ours": (counts[hi][1] - counts[lo][1]) * per}


def run_ours(bench, row, n, repetitions):
    filt = "BM_DemPacking/%s/%d/[12]/-1/real_time$" % (row, n)
    cmd = [bench, "--benchmark_filter=" + filt, "--benchmark_repetitions=%d" % repetitions,
           "--benchmark_format=json"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        fail("xfdem_bench failed:\n" + done.stderr[-3000:], 1)
    rows = [b for b in json.loads(done.stdout)["benchmarks"] if b.get("run_type") == "iteration"]
    out = {}
    for workers in (1, 2):
        mine = [b for b in rows if "/%d/%d/" % (n, workers) in b["name"]]
        if not mine:
            fail("xfdem_bench has no %s (rebuild it)" % filt, 1)
        med = lambda key: statistics.median(b[key] for b in mine)
        out[workers] = {"ns": med("per_particle_step") * 1e9, "contacts": med("contacts_per_particle"),
                        "broad": med("stage_broad_phase_ns"), "contact_stage": med("stage_contacts_ns"),
                        "integration": med("stage_integration_ns"), "dt_us": med("dt_us"), "runs": len(mine)}
    return out, " ".join(cmd[:3])


def measure(args, n, law, export, bench, mpirun_extra):
    """One packing size, one law: both codes' timings and states."""
    work = args.keep and os.path.join(args.keep, "%d_%s" % (n, law))
    if work:
        os.makedirs(work, exist_ok=True)
    tmp = None if work else tempfile.TemporaryDirectory(prefix="bench_liggghts_")
    directory = work or tmp.name
    cmd = [export, str(n), str(args.steps), directory] + EXPORT_OPTION[law]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode not in (0, 1):
        fail("xfdem_packing_export failed:\n" + done.stderr, 1)
    same_bits = "same_bits_1_vs_2_workers yes" in done.stdout
    meta, x0 = read_packing(os.path.join(directory, "packing.txt"))
    write_liggghts(directory, meta, x0, args.steps)
    runs = [run_liggghts(directory, args.ranks, mpirun_extra) for _ in range(args.repetitions)]
    lig = sorted(runs, key=lambda run: run["loop_s"])[len(runs) // 2]  # the median run
    xl, vl = read_dump_last(os.path.join(directory, "after.dump"), n)
    ours_after = np.loadtxt(os.path.join(directory, "xfdem_after.txt"))
    xo, vo = ours_after[:, 0:3], ours_after[:, 3:6]
    m, r = meta["mass"], meta["radius"]
    physics = {
        "ke_ours": 0.5 * m * float((vo * vo).sum()), "ke_lig": 0.5 * m * float((vl * vl).sum()),
        "overlap_ours": mean_overlap(xo, r), "overlap_lig": mean_overlap(xl, r),
        "moved": float(np.linalg.norm(xo - x0, axis=1).max()),
        "differ": float(np.linalg.norm(xo - xl, axis=1).max()),
    }
    ours, bench_cmd = run_ours(bench, BENCH_ROW[law], n, args.repetitions)
    ir = instructions(n, law, export, directory, meta, x0) if n in args.instructions else None
    if tmp:
        tmp.cleanup()
    label = {"frictionless": "frictionless", "friction": "mu %g" % meta.get("friction", 0),
             "hertz": "hertz, mu %g" % meta.get("friction", 0)}[law]
    return {"n": n, "law": label, "meta": meta, "lig": lig, "ours": ours, "physics": physics, "same_bits": same_bits,
            "bench_cmd": bench_cmd, "ir": ir}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[10000, 60000])
    ap.add_argument("--steps", type=int, default=1000, help="LIGGGHTS steps and steps of the physics check")
    ap.add_argument("--repetitions", type=int, default=3, help="runs of each code (median)")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--keep", help="keep the files of each run in this directory")
    ap.add_argument("--instructions", type=int, nargs="*", default=[], metavar="N",
                    help="also count instructions per particle-step under callgrind at these sizes (slow)")
    ap.add_argument("--friction", action="store_true",
                    help="also the frictional packing (when the kernel has friction)")
    ap.add_argument("--hertz", action="store_true",
                    help="also the Hertz-Mindlin packing with friction (when the kernel has the hertz law)")
    args = ap.parse_args()

    needed = [("liggghts", "liggghts"), ("mpirun", "openmpi-bin")]
    if args.instructions:
        needed.append(("valgrind", "valgrind"))
    for tool, package in needed:
        if shutil.which(tool) is None:
            fail("'%s' not found. Install it with:  sudo apt-get install %s\n"
                 "(Debian's liggghts package brings Open MPI; nothing is installed by this script)" % (tool, package))
    export = os.path.join(args.build, "bench", "xfdem_packing_export")
    bench = os.path.join(args.build, "bench", "xfdem_bench")
    for exe in (export, bench):
        if not os.access(exe, os.X_OK):
            fail("%s missing: cmake --preset release && cmake --build --preset release "
                 "--target xfdem_bench xfdem_packing_export" % exe)
    # Open MPI refuses root without --allow-run-as-root; --oversubscribe lets
    # 2 ranks start on a machine that reports fewer slots.
    mpirun_extra = ["--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])

    laws = ["frictionless"]
    notes = []
    for law, wanted, missing in (("friction", args.friction, "Coulomb friction (DemDesc::friction)"),
                                 ("hertz", args.hertz, "hertz law with friction")):
        if not wanted:
            continue
        listed = subprocess.run([bench, "--benchmark_list_tests", "--benchmark_filter=" + BENCH_ROW[law]],
                                capture_output=True, text=True).stdout
        if BENCH_ROW[law] in listed:
            laws.append(law)
        else:
            notes.append("%s: waiting, this kernel has no %s." % (law, missing))

    load_before = os.getloadavg()
    results = [measure(args, n, law, export, bench, mpirun_extra) for law in laws for n in args.sizes]
    load_after = os.getloadavg()

    print("Dense settled packing. LIGGGHTS: %d steps on %d MPI ranks, the median of %d runs; xfdem:"
          " Google Benchmark, median of %d." % (args.steps, args.ranks, args.repetitions, args.repetitions))
    print("Machine: %d cores; load average (1 min) %.1f before, %.1f after." % (
        os.cpu_count(), load_before[0], load_after[0]))
    print("ns per particle-step (wall time):\n")
    print("| law | N | dt (us) | LIGGGHTS %d ranks | xfdem 1 worker | xfdem 2 workers | LIGGGHTS / xfdem 2 | "
          "2 vs 1 worker | same bits 1 vs 2 |" % args.ranks)
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for res in results:
        lig, ours = res["lig"], res["ours"]
        lig_ns = lig["loop_s"] / (lig["atoms"] * lig["steps"]) * 1e9
        print("| %s | %d | %.2f | %.1f | %.1f | %.1f | %.2fx | %.2fx | %s |" % (
            res["law"], res["n"], res["meta"]["dt"] * 1e6, lig_ns, ours[1]["ns"], ours[2]["ns"],
            lig_ns / ours[2]["ns"], ours[1]["ns"] / ours[2]["ns"], "yes" if res["same_bits"] else "NO"))
    print("\nWhere the time goes, ns per particle-step. LIGGGHTS: its timing breakdown (Other holds the fixes:"
          " integration, walls, gravity); xfdem: the kernel's stage profile (separate untimed run):\n")
    print("| law | N | code | stages | total |")
    print("|---|---:|---|---|---:|")
    for res in results:
        lig, ours = res["lig"], res["ours"]
        per = 1e9 / (lig["atoms"] * lig["steps"])
        split = ", ".join("%s %.1f" % (k, v * per) for k, v in lig["stages"].items())
        print("| %s | %d | LIGGGHTS %d ranks | %s; %d list builds | %.1f |" % (
            res["law"], res["n"], args.ranks, split, lig["builds"], lig["loop_s"] * per))
        for w in (1, 2):
            o = ours[w]
            print("| %s | %d | xfdem %d worker%s | broad phase %.1f, contacts %.1f, integration %.1f | %.1f |" % (
                res["law"], res["n"], w, "s" if w == 2 else "", o["broad"], o["contact_stage"], o["integration"],
                o["ns"]))
    print("\nSame physics after %d steps from rest (mean overlap over touching pairs; kinetic energy of translation;"
          " largest |x_xfdem - x_LIGGGHTS| against the largest displacement):\n" % args.steps)
    print("| law | N | kinetic energy xfdem (J) | LIGGGHTS (J) | mean overlap xfdem (um) | LIGGGHTS (um) | "
          "touching pairs x2 / N, xfdem | LIGGGHTS | max position difference (um) | max displacement (um) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for res in results:
        p = res["physics"]
        print("| %s | %d | %.6e | %.6e | %.4f | %.4f | %.2f | %.2f | %.3g | %.3g |" % (
            res["law"], res["n"], p["ke_ours"], p["ke_lig"], p["overlap_ours"][0] * 1e6, p["overlap_lig"][0] * 1e6,
            p["overlap_ours"][1], p["overlap_lig"][1], p["differ"] * 1e6, p["moved"] * 1e6))
    counted = [res for res in results if res["ir"]]
    if counted:
        print("\nInstructions per particle-step on one core (callgrind, 60 minus 10 steps; LIGGGHTS 1 rank, xfdem 1"
              " worker; independent of the machine's load):\n")
        print("| law | N | LIGGGHTS | xfdem | LIGGGHTS / xfdem |")
        print("|---|---:|---:|---:|---:|")
        for res in counted:
            ir = res["ir"]
            print("| %s | %d | %.0f | %.0f | %.2fx |" % (res["law"], res["n"], ir["lig"], ir["ours"],
                                                         ir["lig"] / ir["ours"]))
    print()
    for note in notes:
        print(note)
    print("LIGGGHTS: %s (in a directory holding packing.data and in.packing)" % results[0]["lig"]["command"])
    print("xfdem: %s" % results[0]["bench_cmd"])
    return 0 if all(res["same_bits"] for res in results) else 1


if __name__ == "__main__":
    sys.exit(main())
