"""Case I and Case II (paper figs 9-14): particles dropped on the V2 rod, the
FE-DEM run (conforming mesh, a node pair at the interface) against the X-FE-DEM
run (uniform mesh, enriched cut element). One handler for both cases: report.py
calls it once per case prefix (case1, case2) with that case's runs.

Measured from each pair of CSVs (columns named by the scene's probes):
- impacts of the lowest particle on the rod: the samples where its contact force
  with the top goes from <= 0 to > 0 (0 when apart; the `linear` law can leave
  it slightly negative at the end of a contact). The samples are
  output.every apart and a contact lasts about pi sqrt(m/k), so a contact could
  fall between two samples; such an interval shows as a change of the particle's
  velocity other than -g dt with no contact force at either end, and is counted.
- FE-DEM vs X-FE-DEM: the two runs integrate the same function space (the
  enriched cut element spans the conforming node pair), so they agree to
  round-off; the round-off differs, and every impact amplifies it. Reported:
  max |FE-DEM - X-FE-DEM| of the positions, the tip displacement and the contact
  forces before the second impact (samples t < t_2) and over the whole run.
- resting state: the rod's fundamental is damped only by Newmark's gamma > 1/2
  (a ratio of about (gamma - 1/2) omega dt / 2 ~ 3e-4), so at the end the rod
  still oscillates with the particles riding on it. The static values are
  compared with the means over the last whole periods of the loaded fundamental
  (the eigenproblem of the scene's conforming mesh with the particles attached
  by their contact springs; the bare rod's omega_1 is given too), after the last
  sample at which a contact was open. The continuum's modes of a fixed-free bar
  are odd multiples of omega_1, so whole periods remove them all; the mean is
  the trapezoidal integral over the window (its start interpolated) divided by
  its length. Closed forms: overlap of the lowest particle with the top W/k_1
  (W the particles' total weight), the pair's overlap m_2 g / K_pair with
  K_pair = k_1 k_2 / (k_1 + k_2), the tip -W L/(E A) - W/k_interface (the rod
  carries no gravity), and the mean contact forces W and m_2 g.
- energy: E_total = kinetic + elastic + potential (no dashpot or load work added
  back) may only fall; its largest one-sample rise should be round-off.
"""
import math

import numpy as np

import v2_rod

CASES = ("case1", "case2")
LABEL = {"case1": "Case I", "case2": "Case II"}
METHOD = {"fem": "FE-DEM", "xfem": "X-FE-DEM"}
_energy = {}  # case -> {method: run}, kept across the two calls for the shared energy figure


# ---- scene -> parameters ------------------------------------------------------------
def parameters(scene, where):
    def need(cond, what):
        if not cond:
            raise ValueError(f"{where}: not a Case I/II scene ({what})")

    need(scene.get("dimension") == 1, "dimension must be 1")
    c = scene.get("continuum")
    need(c is not None and c.get("type", "bar") == "bar", "needs a bar continuum")
    need(c.get("base", "fixed") == "fixed", "base must be fixed")
    need(c.get("tip_load", {"shape": "none"}).get("shape", "none") == "none", "no tip load")
    itf = c.get("interface")
    need(itf is not None and itf.get("behaviour", "tied") == "tied", "needs a tied interface")
    dem = scene["dem"]
    need(not dem.get("planes"), "no planes: the rod's top is the only support")
    parts = sorted(dem["particles"], key=lambda p: float(p["position"][0]))
    need(1 <= len(parts) <= 2, "one or two particles")
    nm = c.get("newmark", {})
    P = dict(
        method=c.get("method", "xfem"), L=float(c["length"]), E=float(c["youngs_modulus"]),
        A=float(c["area"]), rho=float(c["density"]), elements=int(c["elements"]),
        xi=float(itf["position"]), k_if=float(itf["stiffness"]),
        beta=float(nm.get("beta", 0.25)), gamma=float(nm.get("gamma", 0.5)),
        dt=float(scene["time"]["dt"]), t_end=float(scene["time"]["end"]),
        g=-float(scene["gravity"][0]), integrator=dem.get("integrator", "abm4"),
        law=dem.get("contact", {}).get("law", "linear"),
        particles=[dict(name=p["name"], m=float(p["mass"]), r=float(p["radius"]),
                        k=float(p["stiffness"])) for p in parts])
    probes = {}
    for p in scene["output"]["probes"]:
        q = p.get("quantity")
        if q in ("position", "velocity") and "particle" in p:
            probes[(q, p["particle"])] = p["name"]
        elif q in ("displacement", "velocity") and "bar_at" in p and float(p["bar_at"]) == P["L"]:
            probes[("tip_" + q,)] = p["name"]
        elif q == "contact_force":
            probes[("force",) + tuple(p["between"])] = p["name"]
        elif q == "energy":
            probes[("energy", p["of"])] = p["name"]
    P["probes"] = probes
    return P


def _name(P, *key):
    """Probe name of key; a contact force is found whichever way its pair is written."""
    if key in P["probes"]:
        return P["probes"][key]
    if key[0] == "force" and ("force", key[2], key[1]) in P["probes"]:
        return P["probes"][("force", key[2], key[1])]
    raise KeyError(f"the scene has no probe for {' '.join(key)}")


# ---- the loaded fundamental -----------------------------------------------------------
def loaded_omegas(P):
    """omega_1 of the bare rod's mesh, and of the mesh with the particles hung on its
    top by their contact springs (K = k_1 to the top, series springs between particles)."""
    mesh = v2_rod.Mesh(P)
    bare = v2_rod.eigen(mesh.M, mesh.K)[0][0]
    n, parts = mesh.n, P["particles"]
    N = n + len(parts)
    M = np.zeros((N, N))
    K = np.zeros((N, N))
    M[:n, :n], K[:n, :n] = mesh.M, mesh.K
    below = mesh.tip
    for i, p in enumerate(parts):
        j = n + i
        M[j, j] = p["m"]
        k = p["k"] if i == 0 else parts[i - 1]["k"] * p["k"] / (parts[i - 1]["k"] + p["k"])
        K[below, below] += k
        K[j, j] += k
        K[below, j] -= k
        K[j, below] -= k
        below = j
    return bare, v2_rod.eigen(M, K)[0][0]


def window_mean(t, y, t0):
    """Mean of y over [t0, t[-1]]: trapezoids, y(t0) interpolated."""
    i = int(np.searchsorted(t, t0, side="right"))
    ts = np.concatenate(([t0], t[i:]))
    ys = np.concatenate(([np.interp(t0, t, y)], y[i:]))
    return float(np.sum(0.5 * (ys[1:] + ys[:-1]) * np.diff(ts)) / (ts[-1] - ts[0]))


def rod_impacts(t, P, run):
    """Impacts of the lowest particle on the rod: (time, how) with time the first
    sample at or after the contact began. Sampled: the force on the top goes from
    <= 0 to > 0. Between samples: the force is <= 0 at both ends of an interval
    but the particles' total momentum rose by more than gravity allows (only the
    top pushes them up; pair forces cancel in the sum)."""
    f = run.col(_name(P, "force", P["particles"][0]["name"], "bar"))
    out = [(float(t[i]), "sampled") for i in range(1, len(f)) if f[i - 1] <= 0.0 < f[i]]
    mom = np.zeros(len(t) - 1)
    scale = np.zeros(len(t) - 1)
    for p in P["particles"]:
        v = run.col(_name(P, "velocity", p["name"]))
        mom += p["m"] * (np.diff(v) + P["g"] * np.diff(t))
        scale += p["m"] * (1.0 + np.abs(v[1:]))
    quiet = (f[:-1] <= 0.0) & (f[1:] <= 0.0)
    out += [(float(t[i + 1]), "between samples") for i in np.nonzero(quiet & (mom > 1e-9 * scale))[0]]
    return sorted(out)


def missed_contacts(t, P, run):
    """Sample intervals where a particle's velocity changed by other than -g dt while
    no contact force of it was positive at either end (a contact between samples)."""
    forces = [run.col(name) for key, name in P["probes"].items() if key[0] == "force"]
    free = np.ones(len(t) - 1, dtype=bool)
    for f in forces:
        free &= (f[:-1] <= 0.0) & (f[1:] <= 0.0)
    count = 0
    for p in P["particles"]:
        v = run.col(_name(P, "velocity", p["name"]))
        dv = np.diff(v) + P["g"] * np.diff(t)
        count += int(np.sum(free & (np.abs(dv) > 1e-9 * (1.0 + np.abs(v[1:])))))
    return count


# ---- the handler ------------------------------------------------------------------------
def analyse(runs, out_dir, plt):
    case = runs[0].case
    for r in runs:
        r.params = parameters(r.scene, r.name)
    by = {r.params["method"]: r for r in runs}
    if set(by) != {"fem", "xfem"} or len(runs) != 2:
        raise ValueError(f"{case}: want one fem and one xfem run, have {', '.join(r.name for r in runs)}")
    fe, xf = by["fem"], by["xfem"]
    P = xf.params
    for key in ("L", "E", "A", "rho", "elements", "xi", "k_if", "g", "dt", "t_end", "particles"):
        if fe.params[key] != P[key]:
            raise ValueError(f"{fe.name}: {key} differs from {xf.name}")
    t = xf.col("t")
    if not np.array_equal(t, fe.col("t")):
        raise ValueError(f"{fe.name}, {xf.name}: different sample times")
    parts = P["particles"]
    low = parts[0]["name"]
    f_top = _name(P, "force", low, "bar")
    label = LABEL.get(case, case)
    tables, long_rows = [], []
    k1 = parts[0]["k"]

    # --- impacts and FE-DEM vs X-FE-DEM ---
    hits = {m: rod_impacts(t, P, by[m]) for m in by}
    if min(len(h) for h in hits.values()) < 2:
        raise ValueError(f"{case}: fewer than two impacts of {low} on the rod")
    t2 = min(hits["fem"][1][0], hits["xfem"][1][0])
    before = t < t2
    compared = [(_name(P, "position", p["name"]), "m") for p in parts]
    compared += [(_name(P, "tip_displacement"), "m"), (f_top, "N")]
    if len(parts) == 2:
        compared.append((_name(P, "force", parts[0]["name"], parts[1]["name"]), "N"))
    rows = []
    for name, unit in compared:
        d = np.abs(fe.col(name) - xf.col(name))
        scale = float(np.max(np.abs(xf.col(name))))
        rows.append([name, unit, f"{np.max(d[before]):.2e}", f"{np.max(d):.2e}", f"{scale:.4g}"])
        long_rows += [[case, xf.name, k1, "fem_vs_xfem", f"max_abs_diff_{name}_before_2nd_impact",
                       float(np.max(d[before]))],
                      [case, xf.name, k1, "fem_vs_xfem", f"max_abs_diff_{name}", float(np.max(d))]]
    missed = {m: missed_contacts(t, P, by[m]) for m in by}
    tables.append(dict(
        title=(f"{label}: max |FE-DEM - X-FE-DEM| ({fe.name} vs {xf.name}), before the second impact "
               f"of {low} on the rod (t < {t2:g} s) and over 0-{P['t_end']:g} s"),
        columns=["probe", "unit", f"t < {t2:g} s", "whole run", "max |X-FE-DEM|"],
        rows=rows,
        note=(f"impacts of {low} on the rod ({f_top} from 0 to > 0 at a sample, or a rise of the "
              f"particles' momentum between two force-free samples): {len(hits['fem'])} FE-DEM, "
              f"{len(hits['xfem'])} X-FE-DEM; the first at "
              f"{', '.join(f'{x:g} s ({how})' for x, how in hits['xfem'][:3])} (X-FE-DEM, first sample "
              f"at or after the contact began). Sample intervals with a contact (any) wholly between "
              f"samples: {missed['fem']} FE-DEM, {missed['xfem']} X-FE-DEM.")))

    # --- resting state, energy ---
    om_bare, om_load = loaded_omegas(P)
    period = 2.0 * math.pi / om_load
    W = sum(p["m"] for p in parts) * P["g"]
    ref = {"overlap_top": W / k1, "tip_u": -W * P["L"] / (P["E"] * P["A"]) - W / P["k_if"], "f_top": W}
    if len(parts) == 2:
        k_pair = parts[0]["k"] * parts[1]["k"] / (parts[0]["k"] + parts[1]["k"])
        ref["overlap_pair"] = parts[1]["m"] * P["g"] / k_pair
        ref["f_pair"] = parts[1]["m"] * P["g"]
    meas, info = {}, {}
    for m, r in by.items():
        open_ = np.zeros(len(t), dtype=bool)
        for key, name in P["probes"].items():
            if key[0] == "force":
                open_ |= r.col(name) <= 0.0
        t_open = float(t[np.nonzero(open_)[0][-1]]) if np.any(open_) else 0.0
        n_per = int(math.floor((t[-1] - t_open) / period))
        if n_per < 1:
            raise ValueError(f"{r.name}: no whole period of the fundamental after the last open contact")
        t0 = t[-1] - n_per * period
        tip = r.col(_name(P, "tip_displacement"))
        y1 = r.col(_name(P, "position", low))
        vals = {"overlap_top": window_mean(t, parts[0]["r"] - (y1 - (P["L"] + tip)), t0),
                "tip_u": window_mean(t, tip, t0), "f_top": window_mean(t, r.col(f_top), t0)}
        if len(parts) == 2:
            y2 = r.col(_name(P, "position", parts[1]["name"]))
            vals["overlap_pair"] = window_mean(t, parts[0]["r"] + parts[1]["r"] - (y2 - y1), t0)
            vals["f_pair"] = window_mean(t, r.col(_name(P, "force", low, parts[1]["name"])), t0)
        e = r.col(_name(P, "energy", "total"))
        rise = float(np.max(np.diff(e)))
        vals["rise"] = rise
        meas[m] = vals
        info[m] = (t_open, n_per, t0, e)
        for key, val in vals.items():
            long_rows.append([case, r.name, k1, P["integrator"],
                              "max_energy_rise_J" if key == "rise" else f"rest_{key}_mean", val])
            if key in ref:
                long_rows.append([case, r.name, k1, P["integrator"], f"rest_{key}_rel_err",
                                  (val - ref[key]) / abs(ref[key])])

    def rel(m, key):
        return (meas[m][key] - ref[key]) / abs(ref[key])

    checks = [("overlap_top", f"overlap {low} / top [m]", f"W/k_1 = {ref['overlap_top']:.6e}")]
    if len(parts) == 2:
        checks.append(("overlap_pair", f"overlap {parts[0]['name']} / {parts[1]['name']} [m]",
                       f"m_2 g/K_pair = {ref['overlap_pair']:.6e}"))
    checks.append(("tip_u", "tip u [m]", f"-WL/(EA) - W/k_if = {ref['tip_u']:.6e}"))
    checks.append(("f_top", f"{f_top} [N]", f"W = {ref['f_top']:.6g}"))
    if len(parts) == 2:
        checks.append(("f_pair", f"{_name(P, 'force', low, parts[1]['name'])} [N]",
                       f"m_2 g = {ref['f_pair']:.6g}"))
    rows = []
    for key, what, closed in checks:
        rows.append([what, f"{meas['fem'][key]:.6e} ({rel('fem', key):+.1e})",
                     f"{meas['xfem'][key]:.6e} ({rel('xfem', key):+.1e})", closed])
    e0 = {m: info[m][3][0] for m in by}
    rows.append(["largest one-sample rise of E_total [J]",
                 f"{meas['fem']['rise']:.2e} ({meas['fem']['rise'] / abs(e0['fem']):.0e} E_0)",
                 f"{meas['xfem']['rise']:.2e} ({meas['xfem']['rise'] / abs(e0['xfem']):.0e} E_0)",
                 "0 (round-off)"])
    rows.append(["E_total lost over the run [J]",
                 f"{e0['fem'] - info['fem'][3][-1]:.6g}", f"{e0['xfem'] - info['xfem'][3][-1]:.6g}",
                 f"of E_0 = {e0['xfem']:.6g}"])
    win = "; ".join(f"{METHOD[m]}: last open contact at {info[m][0]:g} s, {info[m][1]} periods from "
                    f"{info[m][2]:.4f} s" for m in ("fem", "xfem"))
    tables.append(dict(
        title=(f"{label}: resting state (means over whole periods of the loaded fundamental) vs the "
               f"static closed form, and energy"),
        columns=["quantity", "FE-DEM (rel. diff.)", "X-FE-DEM (rel. diff.)", "closed form"],
        rows=rows,
        note=(f"W = {W:g} N (particles' weight; the rod carries none). omega_1 = {om_load:.5f} rad/s "
              f"with the particles on the top (bare rod mesh: {om_bare:.5f} rad/s), period {period:.5f} s. "
              f"{win}.")))

    figures = [_plot_case(case, P, fe, xf, hits, t2, out_dir, plt)]
    first = not _energy
    _energy[case] = (P, by)
    path = _plot_energy(out_dir, plt)
    if first:
        figures.append(path)
    return tables, long_rows, figures


# ---- figures -------------------------------------------------------------------------------
def _pair_plot(ax, t, yf, yx, color, what, every=4):
    ax.plot(t, yf, "-", color=color, lw=1.2, label=f"{what}, FE-DEM")
    ax.plot(t[::every], yx[::every], "o", ms=2.4, mfc="none", mew=0.7, color=color, alpha=0.8,
            label=f"{what}, X-FE-DEM")


def _plot_case(case, P, fe, xf, hits, t2, out_dir, plt):
    t = xf.col("t")
    parts = P["particles"]
    low = parts[0]["name"]
    tip = _name(P, "tip_displacement")
    f_top = _name(P, "force", low, "bar")
    two = len(parts) == 2
    nrow = 4 if two else 3
    fig, axes = plt.subplots(nrow, 1, figsize=(11, 2.9 * nrow + 0.6), sharex=True)
    ax = axes[0]
    colors = ["C0", "C1"]
    for p, c in zip(parts, colors):
        name = _name(P, "position", p["name"])
        _pair_plot(ax, t, fe.col(name), xf.col(name), c, f"{name} ({p['m']:g} kg)")
    _pair_plot(ax, t, P["L"] + fe.col(tip), P["L"] + xf.col(tip), "k", f"rod top {P['L']:g} + {tip}")
    ax.set_ylabel("height [m]")
    ax.legend(loc="upper right", fontsize=8, ncol=3 if two else 3)
    ax.set_title(f"{LABEL.get(case, case)}: {len(parts)} particle{'s' if two else ''} dropped on the rod, "
                 f"FE-DEM vs X-FE-DEM (paper figs {'11-14' if two else '9-10'})")

    ax = axes[1]
    _pair_plot(ax, t, fe.col(tip) * 1e3, xf.col(tip) * 1e3, "C2", tip)
    ref = -sum(p["m"] for p in parts) * P["g"] * (P["L"] / (P["E"] * P["A"]) + 1.0 / P["k_if"])
    ax.axhline(ref * 1e3, color="k", ls=":", lw=1, label=f"static -WL/(EA) - W/k_if = {ref * 1e3:.4f} mm")
    ax.set_ylabel("rod tip displacement [mm]")
    ax.legend(loc="lower right", fontsize=8, ncol=3)

    if two:
        ax = axes[2]
        _pair_plot(ax, t, fe.col(f_top) / 1e3, xf.col(f_top) / 1e3, "C3", f"{f_top} (particle-rod)")
        ax.set_ylabel("contact force [kN]")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.legend(loc="upper right", fontsize=8)
        ax = axes[3]
        fp = _name(P, "force", low, parts[1]["name"])
        _pair_plot(ax, t, fe.col(fp) / 1e3, xf.col(fp) / 1e3, "C4", f"{fp} (particle-particle)")
        ax.set_ylabel("contact force [kN]")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.legend(loc="upper right", fontsize=8)
    else:
        ax = axes[2]
        _pair_plot(ax, t, fe.col(f_top) / 1e3, xf.col(f_top) / 1e3, "C3", f"{f_top} (particle-rod)")
        ax.set_ylabel("contact force [kN]")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
        for x, _ in hits["xfem"][:2]:
            ax.axvline(x, color="0.5", lw=0.6, ls="--")
    axes[0].text(hits["xfem"][1][0], 0.5, "  dashed: 1st and 2nd impact\n  of the lowest particle",
                 transform=axes[0].get_xaxis_transform(), fontsize=8, color="0.35", va="center")
    axes[-1].set_xlabel("t [s]")
    axes[-1].set_xlim(0, P["t_end"])
    fig.tight_layout()
    path = f"{out_dir}/{case}_fig{'11_14' if two else '9_10'}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_energy(out_dir, plt):
    cases = sorted(_energy)
    fig, axes = plt.subplots(len(cases), 2, figsize=(12, 3.6 * len(cases)), squeeze=False)
    for row, case in zip(axes, cases):
        P, by = _energy[case]
        ax = row[0]
        r = by["xfem"]
        t = r.col("t")
        lines = []
        for of, c in (("total", "k"), ("potential", "C2")):
            lines += ax.plot(t, r.col(_name(P, "energy", of)) / 1e3, "-", color=c, lw=1.2,
                             label=f"E_{of} (left axis)")
        lines += ax.plot(t, by["fem"].col(_name(P, "energy", "total")) / 1e3, "--", color="0.6", lw=1.0,
                         label="E_total, FE-DEM (left axis)")
        ax.set_ylabel("total, potential [kJ]")
        right = ax.twinx()
        for of, c in (("kinetic", "C0"), ("elastic", "C3")):
            lines += right.plot(t, r.col(_name(P, "energy", of)) / 1e3, "-", color=c, lw=0.9,
                                label=f"E_{of} (right axis)")
        right.set_ylabel("kinetic, elastic [kJ]")
        ax.set_title(f"{LABEL.get(case, case)}: energies, X-FE-DEM (potential datum y = 0)", fontsize=10)
        ax.legend(lines, [x.get_label() for x in lines], loc="center right", fontsize=8)
        ax = row[1]
        for m, c in (("fem", "C0"), ("xfem", "C3")):
            e = by[m].col(_name(P, "energy", "total"))
            rise = np.diff(e)
            ax.plot(t, e - e[0], "-" if m == "fem" else "--", color=c, lw=1.1,
                    label=f"{METHOD[m]}: largest one-sample rise {np.max(rise):.1e} J")
        ax.set_ylabel("E_total(t) - E_total(0) [J]")
        ax.set_title(f"{LABEL.get(case, case)}: total energy never rises", fontsize=10)
        ax.legend(loc="upper right", fontsize=8)
        for a in row:
            a.grid(alpha=0.3)
            a.set_xlim(0, P["t_end"])
            a.set_xlabel("t [s]")
    fig.tight_layout()
    path = f"{out_dir}/cases_energy.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
