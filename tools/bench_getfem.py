#!/usr/bin/env python3
"""The plate's step and build side by side with GetFEM (docs/benchmarks.md, "2D plate").

    /usr/bin/python3 tools/bench_getfem.py [--build build/release] [--repetitions 5]
        [--png out/plate_step_cost.png] [--case uncut|tied_cut] [--before OTHER/xfdem_bench]

Both sides solve the plate of scenes/plate_tension.json (steel, plane stress,
t = 0.02 m, 2 m x 1 m, rollers on the left (x) and bottom (y) edges, a step
traction of 1e6 Pa in x on the right edge) on 10 x 4, 32 x 16 and 100 x 50 Q4
cells, Newmark (1/4, 1/2), dt = 1e-5 s, the effective matrix M + beta dt^2 K
factored once and one back-substitution per step:

  xfdem:  bench/bm_plate.cpp through build/release/bench/xfdem_bench
          (BM_PlateStep, BM_PlateSolve, BM_PlateBuild), medians of
          --repetitions Google Benchmark runs (CPU time); the factor is the
          sparse LDL^T on Eigen's AMD ordering (xfem::SparseLdlt), and
          BM_PlateSolve/.../sparse:0 times a profile LDL^T of the same matrix
          (what the step used before). --before runs another build's
          xfdem_bench (e.g. one built from the previous commit) in the same
          run and prints its BM_PlateStep next to this one's;
  GetFEM: its Python interface (Debian's python3-getfem 5.4): FEM_QK(2,1) on
          a cartesian mesh, 2 x 2 Gauss, K, M and the traction by the generic
          assembly, the held components removed; M + beta dt^2 K factored once
          by SuperLU and per step the predictor (numpy), K u_pred
          (Spmat.mult), the back-substitution and the updates; medians of
          --repetitions timed loops (process time). GetFEM's own factor-once
          object, Precond('superlu', ...), crashes in this build (a
          segmentation fault, even on a 5 x 5 identity), so the factor and
          the back-substitution are SuperLU's through SciPy
          (scipy.sparse.linalg.splu, MMD on A^T + A), the library that
          Precond wraps; "GetFEM build" is GetFEM's mesh, assembly and
          reduction plus SciPy's two factorisations (M and M + beta dt^2 K).

Before timing, the two are checked to solve the same problem: the right edge's
mid-node x displacement after 200 steps from rest agrees to round-off
(printed). Prints one markdown table (per-step cost, back-substitution alone,
build / assembly, the ratios xfdem / GetFEM, the bytes of xfdem's profile
factor and of SuperLU's L and U) and writes the cost model's log-log plot (per-step cost against
unknowns) to --png.

--case tied_cut: the same plate with scenes/plate_crack.json's tied crack
(x = 1.03, across the whole plate, off the mesh's lines at every size; faces
tied by k_n = k_t = 1e13 Pa/m, traction k [u] per unit area):

  xfdem:  BM_PlateTiedCutStep (bench/bm_plate.cpp), Heaviside unknowns on the
          nodes of the cut cells, the penalty t k [u].[v] on the crack;
  GetFEM: a level set x - 1.03 (LevelSet, MeshLevelSet), the Q4 space
          enriched where it cuts (MeshFem('levelset'): the same span as
          xfdem's standard + Heaviside unknowns), the cut cells integrated on
          their sub-triangles (MeshIm('levelset', ..., 'all', IM_TRIANGLE(6)),
          exact for the products), the penalty by the generic assembly on the
          level set ('boundary(a)', Xfem_plus(u) - Xfem_minus(u)); the step
          and the factor as the uncut case's.

Before timing, both solve the plate at every size, statically (K u = f) and
for 200 steps from rest, and compare u_x at (2, 0.5), the opening and the
sliding at (1.03, 0.5) (xfdem through its command line and the scene's
probes); the script stops without timing if any differs by more than
TIED_CUT_TOLERANCE relative. Then one table: xfdem's step (medians of
--repetitions, energy check every 16 steps and off), GetFEM's, their ratio
and whether the step is <= 1/5 of GetFEM's; the load average at the start and
end of the timing. --png and --before apply to the uncut case only.

Needs: python3-getfem (`apt-get install python3-getfem`), numpy, scipy,
matplotlib (Debian's python3-numpy, python3-scipy, python3-matplotlib).
"""
import argparse
import json
import os
import subprocess
import sys
import time

SIZES = [(10, 4), (32, 16), (100, 50)]
E, NU, RHO, T = 2e11, 0.3, 7800.0, 0.02
LX, LY = 2.0, 1.0
TRACTION = 1e6
DT, BETA, GAMMA = 1e-5, 0.25, 0.5
CHECK_STEPS = 200
# scenes/plate_crack.json's tied crack: x = 1.03 across the plate, k = (k_n, k_t).
CRACK_X = 1.03
CRACK_K = (1e13, 1e13)
UNIT_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def import_getfem():
    try:
        import getfem  # noqa: F401
    except ImportError:
        sys.exit("bench_getfem.py: GetFEM's Python interface is missing: apt-get install python3-getfem "
                 "(and run this script with /usr/bin/python3, which sees Debian's packages)")
    import getfem
    return getfem


class GetfemPlate:
    """The plate in GetFEM, reduced to its free unknowns, factored once.

    cut: the tied crack of scenes/plate_crack.json (x = CRACK_X across the
    whole plate, faces tied by CRACK_K) by GetFEM's level set: a level set
    x - CRACK_X, the Q4 space enriched where it cuts (MeshFem('levelset'): each
    node whose support is cut gets a second function, discontinuous across the
    level set, so the span is xfdem's standard + Heaviside unknowns), the cut
    cells integrated on their sub-triangles (IM_TRIANGLE(6): exact for the
    biquadratic products), the penalty t k [u].[v] on the level set
    (Xfem_plus - Xfem_minus, 'boundary(a)')."""

    def __init__(self, gf, nx, ny, cut=False):
        import numpy as np
        self.np = np
        self.gf = gf
        mesh = gf.Mesh("cartesian", np.linspace(0.0, LX, nx + 1), np.linspace(0.0, LY, ny + 1))
        if cut:
            ls = gf.LevelSet(mesh, 1, f"x-{CRACK_X!r}")
            mls = gf.MeshLevelSet(mesh)
            mls.add(ls)
            mls.adapt()
            scalar = gf.MeshFem(mesh, 1)
            scalar.set_fem(gf.Fem("FEM_QK(2,1)"))
            mf = gf.MeshFem("levelset", mls, scalar)
            mf.set_qdim(2)
            mim = gf.MeshIm("levelset", mls, "all", gf.Integ("IM_TRIANGLE(6)"))
            mim.set_integ(gf.Integ("IM_GAUSS_PARALLELEPIPED(2,2)"))  # the uncut cells
            mim_faces = gf.MeshIm("levelset", mls, "boundary(a)", gf.Integ("IM_TRIANGLE(6)"))
            self.keep = (mesh, ls, mls, scalar)  # mf is invalid once these are freed
        else:
            mf = gf.MeshFem(mesh, 2)
            mf.set_fem(gf.Fem("FEM_QK(2,1)"))
            mim = gf.MeshIm(mesh, gf.Integ("IM_GAUSS_PARALLELEPIPED(2,2)"))
        self.mf = mf
        right = 1
        mesh.set_region(right, mesh.outer_faces_with_direction([1.0, 0.0], 0.01))
        lam = E * NU / ((1 + NU) * (1 - 2 * NU))
        mu = E / (2 * (1 + NU))
        lam_stress = 2 * lam * mu / (lam + 2 * mu)  # plane stress
        md = gf.Model("real")
        md.add_fem_variable("u", mf)
        md.add_initialized_data("lambda", [lam_stress])
        md.add_initialized_data("mu", [mu])
        md.add_initialized_data("t", [T])
        md.add_initialized_data("rho", [RHO])
        md.add_initialized_data("trac", [TRACTION, 0.0])
        k_all = gf.asm_generic(mim, 2, "t*(lambda*Div(u)*Div(Test_u) + 2*mu*Sym(Grad(u)):Grad(Test_u))", -1, md)
        m_all = gf.asm_generic(mim, 2, "t*rho*u.Test_u", -1, md)
        f_all = gf.asm_generic(mim, 1, "t*trac.Test_u", right, md)
        if cut:
            # xfdem's tied faces: traction k [u] per unit area, k = (k_n, k_t)
            # along the level set's normal and its tangent (docs/xfem2d.md).
            md.add_initialized_data("kn", [CRACK_K[0]])
            md.add_initialized_data("kt", [CRACK_K[1]])
            md.add_macro("jump(a)", "Xfem_plus(a)-Xfem_minus(a)")
            md.add_macro("tang(a)", "a-(a.Normal)*Normal")
            faces = gf.asm_generic(
                mim_faces, 2,
                "t*(kn*(jump(u).Normal)*(jump(Test_u).Normal) + kt*tang(jump(u)).tang(jump(Test_u)))", -1, md)
            k_all = gf.Spmat("add", k_all, faces)
            self.face_length = gf.asm_generic(mim_faces, 0, "1", -1, md)
        # Basic dofs come node by node, x then y (Qdim 2; the level set's
        # enriched functions too, at their node).
        nodes = mf.basic_dof_nodes()
        eps = 1e-9
        assert all(nodes[0, k] == nodes[0, k + 1] and nodes[1, k] == nodes[1, k + 1]
                   for k in range(0, mf.nbdof(), 2))
        free = [k for k in range(mf.nbdof())
                if not ((k % 2 == 0 and nodes[0, k] < eps) or (k % 2 == 1 and nodes[1, k] < eps))]
        self.free = free
        self.k = gf.Spmat("copy", k_all, free, free)
        self.m = gf.Spmat("copy", m_all, free, free)
        self.f = np.ascontiguousarray(f_all[free])
        scaled_k = gf.Spmat("copy", self.k)
        scaled_k.scale(BETA * DT * DT)
        eff = gf.Spmat("add", self.m, scaled_k)
        self.k_static = gf.Spmat("copy", self.k)  # the static check's K (self.k turns CSC below)
        self.k.to_csc()
        # Factor once: Precond('superlu', ...) crashes in Debian's GetFEM 5.4.2
        # (a segmentation fault even on a 5 x 5 identity), so the factor is
        # SuperLU's through SciPy, the library GetFEM's Precond wraps.
        self.eff_factor = splu(to_scipy(eff), permc_spec="MMD_AT_PLUS_A")
        self.mass_factor = splu(to_scipy(self.m), permc_spec="MMD_AT_PLUS_A")
        self.n = len(free)
        tip = [i for i, k in enumerate(free) if k % 2 == 0 and abs(nodes[0, k] - LX) < eps and abs(nodes[1, k] - 0.5 * LY) < eps]
        self.tip = tip[0] if tip else None
        self.rest()

    def jump(self, y):
        """u just right of the crack minus just left of it at height y: (x, y)
        components, xfdem's opening and sliding (the crack runs up, its
        normal points to -x)."""
        np = self.np
        full = np.zeros(self.mf.nbdof())
        full[self.free] = self.u
        # At x = CRACK_X -+ g and -+ 2g: u is linear in x on each side of the
        # crack in a cut cell (bilinear functions, times a Heaviside), so
        # 2 j(g) - j(2g) is the jump at the crack itself, without the
        # strain times the offset that j(g) alone carries.
        g = 1e-6
        pts = np.array([[CRACK_X + g, CRACK_X - g, CRACK_X + 2 * g, CRACK_X - 2 * g], [y] * 4])
        val = self.gf.compute_interpolate_on(self.mf, full, pts)
        return tuple(float(2 * (val[c, 0] - val[c, 1]) - (val[c, 2] - val[c, 3])) for c in range(2))

    def factor_bytes(self):
        """SuperLU's L and U of M + beta dt^2 K: a value and a row index per
        stored entry (CSC; the column pointers left out)."""
        f = self.eff_factor
        return (f.L.nnz + f.U.nnz) * (8 + 4)

    def rest(self):
        np = self.np
        self.u = np.zeros(self.n)
        self.v = np.zeros(self.n)
        self.a = np.asarray(self.mass_factor.solve(self.f - np.ravel(self.k.mult(self.u))))  # M a0 = f(0) - K u0

    def step(self):
        np = self.np
        u_pred = self.u + DT * self.v + ((0.5 - BETA) * DT * DT) * self.a
        v_pred = self.v + ((1.0 - GAMMA) * DT) * self.a
        self.a = self.eff_factor.solve(self.f - np.ravel(self.k.mult(u_pred)))
        self.u = u_pred + (BETA * DT * DT) * self.a
        self.v = v_pred + (GAMMA * DT) * self.a


def to_scipy(a):
    """A GetFEM Spmat as a SciPy CSC matrix (copies the arrays)."""
    from scipy.sparse import csc_matrix
    jc, ir = a.csc_ind()
    n = a.size()
    return csc_matrix((a.csc_val(), ir, jc), shape=(int(n[0]), int(n[1])))


def splu(a, permc_spec):
    from scipy.sparse.linalg import splu as scipy_splu
    return scipy_splu(a, permc_spec=permc_spec)


def build_getfem(gf, nx, ny, cut=False):
    return GetfemPlate(gf, nx, ny, cut)


def median_seconds(fn, repetitions, min_seconds=0.2):
    """Median over repetitions of the process time per call of fn, each repetition
    long enough (>= min_seconds) for the clock."""
    calls = 1
    while True:
        t0 = time.process_time()
        for _ in range(calls):
            fn()
        if time.process_time() - t0 >= min_seconds / 4 or calls >= 1 << 20:
            break
        calls *= 2
    per = []
    for _ in range(repetitions):
        t0 = time.process_time()
        for _ in range(calls * 4):
            fn()
        per.append((time.process_time() - t0) / (calls * 4))
    per.sort()
    return per[len(per) // 2]


def xfdem_medians(bench, repetitions, pattern="BM_Plate(Step|Solve|Build|StiffnessProduct)/"):
    result = subprocess.run(
        [bench, f"--benchmark_filter={pattern}", f"--benchmark_repetitions={repetitions}",
         "--benchmark_report_aggregates_only=true", "--benchmark_format=json"],
        check=True, capture_output=True, text=True)
    medians = {}
    for b in json.loads(result.stdout)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            b["cpu_s"] = b["cpu_time"] * UNIT_NS[b["time_unit"]] * 1e-9
            medians[b["run_name"]] = b
    return medians


def xfdem_probes(cli, nx, ny, scene="plate_tension.json", static=False):
    """The scene's last row of probes (after CHECK_STEPS steps, or the static
    solution), through the command line, as a dict."""
    scene = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", scene)
    args = [cli, "run", scene, "--set", f"continuum.cells=[{nx},{ny}]"]
    if static:
        args += ["--set", "continuum.analysis=\"static\""]
    else:
        args += ["--set", f"time.end={CHECK_STEPS * DT!r}", "--set", f"output.every={CHECK_STEPS * DT!r}"]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout.splitlines()
    return dict(zip(out[0].split(","), (float(v) for v in out[-1].split(","))))


def xfdem_tip(cli, nx, ny):
    """u_x at (2, 0.5) after CHECK_STEPS steps, through the command line."""
    return xfdem_probes(cli, nx, ny)["u_tip"]


# The tied cut's check: GetFEM and xfdem on the same plate must agree to this
# (relative to the value): both integrate the same space exactly, so what is
# left is round-off (different factorisations and sums, over CHECK_STEPS steps).
TIED_CUT_TOLERANCE = 1e-11


def tied_cut(gf, bench, cli, repetitions):
    """--case tied_cut: check that the two agree, then time the step."""
    print("same problem: scenes/plate_crack.json's plate (tied crack at x = %g, k = %g Pa/m) on each size" %
          (CRACK_X, CRACK_K[0]))
    print("  u_tip = u_x at (2, 0.5); at (%g, 0.5) opening = [u_x] and sliding = -[u_y], [.] right minus left" % CRACK_X)
    worst = 0.0
    for nx, ny in SIZES:
        p = build_getfem(gf, nx, ny, cut=True)
        # Static: K u = f (GetFEM: SciPy's solve of the reduced K).
        from scipy.sparse.linalg import spsolve
        np = p.np
        u_dyn = p.u
        p.u = np.asarray(spsolve(to_scipy(p.k_static), p.f))
        theirs_static = (float(p.u[p.tip]), p.jump(0.5)[0])
        p.u = u_dyn
        for _ in range(CHECK_STEPS):
            p.step()
        jx, jy = p.jump(0.5)
        theirs_dyn = (float(p.u[p.tip]), jx, -jy)
        ours_static = xfdem_probes(cli, nx, ny, "plate_crack.json", static=True)
        ours_dyn = xfdem_probes(cli, nx, ny, "plate_crack.json")
        # (The static sliding is zero in both: left out.)
        for label, ours, theirs in (("static", ours_static, theirs_static),
                                    (f"{CHECK_STEPS} steps", ours_dyn, theirs_dyn)):
            for name, t in zip(("u_tip", "opening", "sliding"), theirs):
                o = ours[name]
                rel = abs(o - t) / abs(t)
                worst = max(worst, rel)
                print(f"  {nx} x {ny} ({p.n} unknowns), {label}, {name}: xfdem {o:.17g}, GetFEM {t:.17g}, "
                      f"relative difference {rel:.2e}")
    if not worst <= TIED_CUT_TOLERANCE:
        sys.exit(f"bench_getfem.py: --case tied_cut: the two differ by {worst:.2e} relative "
                 f"(> {TIED_CUT_TOLERANCE:g}); not timed")
    print(f"  largest relative difference {worst:.2e} (the check: <= {TIED_CUT_TOLERANCE:g})")

    load = os.getloadavg()[0]
    ours = xfdem_medians(bench, repetitions, "BM_PlateTiedCutStep/")
    print()
    header = ["cells", "unknowns", "xfdem step", "xfdem step, no energy check", "GetFEM step", "ratio",
              "ratio, no energy check", "step <= 1/5 of GetFEM's"]
    print("| " + " | ".join(header) + " |")
    print("|---|" + "---:|" * (len(header) - 1))
    for nx, ny in SIZES:
        step = ours[f"BM_PlateTiedCutStep/nx:{nx}/ny:{ny}/check:16"]
        step_nocheck = ours[f"BM_PlateTiedCutStep/nx:{nx}/ny:{ny}/check:0"]
        p = build_getfem(gf, nx, ny, cut=True)
        assert p.n == int(step["dofs"]), (p.n, step["dofs"])
        g_step = median_seconds(p.step, repetitions)
        ratio = step["cpu_s"] / g_step
        print(f"| {nx} x {ny} | {p.n} | {seconds_text(step['cpu_s'])} | {seconds_text(step_nocheck['cpu_s'])} "
              f"| {seconds_text(g_step)} | {ratio:.3f} | {step_nocheck['cpu_s'] / g_step:.3f} "
              f"| {'yes' if ratio <= 0.2 else 'no'} |")
    print("\nratio: xfdem / GetFEM (the goal: <= 0.2 for the step)")
    print(f"load average (1 min) at the start of the timing: {load:.2f}, at its end: {os.getloadavg()[0]:.2f}")


def seconds_text(s):
    for unit, scale in (("ns", 1e-9), ("µs", 1e-6), ("ms", 1e-3), ("s", 1.0)):
        if s < 1000 * scale or unit == "s":
            v = s / scale
            return (f"{v:#.3g}" if v < 100 else f"{v:.0f}").rstrip(".") + " " + unit
    return f"{s} s"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build/release")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--png", default="out/plate_step_cost.png")
    parser.add_argument("--case", default="uncut", choices=["uncut", "tied_cut"])
    parser.add_argument("--before", default=None, help="another build's xfdem_bench, timed in the same run")
    args = parser.parse_args()
    gf = import_getfem()
    import numpy as np
    bench = os.path.join(args.build, "bench", "xfdem_bench")
    cli = os.path.join(args.build, "tools", "xfdem")
    for path in (bench, cli):
        if not os.access(path, os.X_OK):
            sys.exit(f"bench_getfem.py: {path} is missing: cmake --preset release && cmake --build --preset release")
    if args.case == "tied_cut":
        tied_cut(gf, bench, cli, args.repetitions)
        return

    print("same problem: the right edge's mid-node u_x after %d steps from rest" % CHECK_STEPS)
    for nx, ny in SIZES[:2]:
        p = build_getfem(gf, nx, ny)
        for _ in range(CHECK_STEPS):
            p.step()
        ours = xfdem_tip(cli, nx, ny)
        theirs = float(p.u[p.tip])
        print(f"  {nx} x {ny}: xfdem {ours:.17g}, GetFEM {theirs:.17g}, relative difference "
              f"{abs(ours - theirs) / abs(theirs):.2e}")

    ours = xfdem_medians(bench, args.repetitions)
    rows, plot = [], []
    for nx, ny in SIZES:
        step = ours[f"BM_PlateStep/nx:{nx}/ny:{ny}/check:16"]
        step_nocheck = ours[f"BM_PlateStep/nx:{nx}/ny:{ny}/check:0"]
        solve = ours[f"BM_PlateSolve/nx:{nx}/ny:{ny}/sparse:1"]
        build = ours[f"BM_PlateBuild/nx:{nx}/ny:{ny}"]
        p = build_getfem(gf, nx, ny)
        assert p.n == int(step["dofs"]), (p.n, step["dofs"])
        g_build = median_seconds(lambda: build_getfem(gf, nx, ny), args.repetitions)
        g_step = median_seconds(p.step, args.repetitions)
        rhs = p.f - np.ravel(p.k.mult(p.u))
        g_solve = median_seconds(lambda: p.eff_factor.solve(rhs), args.repetitions)
        rows.append([f"{nx} x {ny}", p.n,
                     seconds_text(step["cpu_s"]), seconds_text(step_nocheck["cpu_s"]), seconds_text(g_step),
                     f"{step['cpu_s'] / g_step:.2f}",
                     seconds_text(solve["cpu_s"]), seconds_text(g_solve), f"{solve['cpu_s'] / g_solve:.2f}",
                     seconds_text(build["cpu_s"]), seconds_text(g_build), f"{build['cpu_s'] / g_build:.2f}",
                     f"{step['factor_bytes'] / 1e6:.3g} MB", f"{p.factor_bytes() / 1e6:.3g} MB"])
        plot.append((p.n, step["cpu_s"], solve["cpu_s"], g_step, g_solve))

    header = ["cells", "unknowns", "xfdem step", "xfdem step, no energy check", "GetFEM step", "ratio",
              "xfdem back-subst.", "GetFEM back-subst.", "ratio", "xfdem build", "GetFEM build", "ratio",
              "xfdem factor", "SuperLU factor"]
    print()
    print("| " + " | ".join(header) + " |")
    print("|---|" + "---:|" * (len(header) - 1))
    for r in rows:
        print("| " + " | ".join(str(c) for c in r) + " |")
    print("\nratio: xfdem / GetFEM (the goal: <= 0.2 for the step)")

    print("\nwhere the xfdem step goes (y -= K x over K's profile, as the step did it before, and cell by cell, as it does now):\n")
    print("| cells | step | back-substitution, sparse | back-substitution, profile | K x, profile | K x, cell by cell |")
    print("|---|---:|---:|---:|---:|---:|")
    for nx, ny in SIZES:
        cell = f"nx:{nx}/ny:{ny}"
        print(f"| {nx} x {ny} | {seconds_text(ours[f'BM_PlateStep/{cell}/check:16']['cpu_s'])} "
              f"| {seconds_text(ours[f'BM_PlateSolve/{cell}/sparse:1']['cpu_s'])} "
              f"| {seconds_text(ours[f'BM_PlateSolve/{cell}/sparse:0']['cpu_s'])} "
              f"| {seconds_text(ours[f'BM_PlateStiffnessProduct/{cell}/cells:0']['cpu_s'])} "
              f"| {seconds_text(ours[f'BM_PlateStiffnessProduct/{cell}/cells:1']['cpu_s'])} |")

    if args.before:
        before = xfdem_medians(args.before, args.repetitions)
        print(f"\nthe same run, BM_PlateStep of {args.before} (before) and of {bench} (after):\n")
        print("| cells | step before | step after | no check, before | no check, after | GetFEM step | ratio before | ratio after |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for (nx, ny), r in zip(SIZES, plot):
            b16 = before[f"BM_PlateStep/nx:{nx}/ny:{ny}/check:16"]["cpu_s"]
            b0 = before[f"BM_PlateStep/nx:{nx}/ny:{ny}/check:0"]["cpu_s"]
            a0 = ours[f"BM_PlateStep/nx:{nx}/ny:{ny}/check:0"]["cpu_s"]
            print(f"| {nx} x {ny} | {seconds_text(b16)} | {seconds_text(r[1])} | {seconds_text(b0)} | {seconds_text(a0)} "
                  f"| {seconds_text(r[3])} | {b16 / r[3]:.2f} | {r[1] / r[3]:.2f} |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = np.array([r[0] for r in plot], dtype=float)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(n, [r[1] for r in plot], "o-", label="xfdem step")
    ax.loglog(n, [r[2] for r in plot], "o--", label="xfdem back-substitution (sparse)")
    ax.loglog(n, [ours[f"BM_PlateSolve/nx:{nx}/ny:{ny}/sparse:0"]["cpu_s"] for nx, ny in SIZES], "^:",
              label="xfdem profile back-substitution (before)")
    ax.loglog(n, [r[3] for r in plot], "s-", label="GetFEM step")
    ax.loglog(n, [r[4] for r in plot], "s--", label="GetFEM back-substitution")
    ref = plot[0][1] * (n / n[0]) ** 1.5
    ax.loglog(n, ref, ":", color="gray", label=r"$\propto n^{3/2}$ (profile: $n \cdot$ bandwidth)")
    ax.set_xlabel("unknowns n")
    ax.set_ylabel("CPU time per step (s)")
    ax.set_title("Plate, Newmark (1/4, 1/2), factor once")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    os.makedirs(os.path.dirname(args.png) or ".", exist_ok=True)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
