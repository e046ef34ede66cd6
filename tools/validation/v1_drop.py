"""V1, the drop test (paper fig 6): simulated runs against the closed form.

Measured from each run's CSV (columns t, y, v at the scene's output step):
- contacts are the runs of samples with y < r; a contact starts (ends) where
  the free-flight parabola through the last sample before it (the first
  sample after it), with that sample's y and v and y'' = -g, meets y = r;
- the max overlap is r minus the minimum of the polynomial through (y, v) at
  up to five samples around the smallest y, all inside the contact (degree 9
  with five samples; the cubic through two samples if the contact is shorter);
- an apex is the maximum of the cubic through (y, v) at the two samples where
  v changes sign from + to -, between two contacts (exact in free flight, where
  y is a parabola);
- max |y - y_exact| is taken over all samples of the run.
The same estimators applied to the closed form sampled at the same times give
the "sampling floor" row: the part of an error that comes from measuring, not
from integrating.
"""
import math

import numpy as np

import drop_closed_form as cf

CASE = "v1"
N_EVENTS = 3  # apexes, overlaps and durations reported for contacts 1..3


# ---- scene -> closed-form parameters ------------------------------------------
def parameters(scene, where):
    def need(cond, what):
        if not cond:
            raise ValueError(f"{where}: not a V1 drop-test scene ({what})")

    need(scene.get("dimension") == 1, "dimension must be 1")
    need("continuum" not in scene, "has a continuum")
    dem = scene["dem"]
    need(len(dem["particles"]) == 1, "needs exactly one particle")
    need(dem.get("contact", {}).get("law", "linear") == "linear", "contact law must be linear")
    planes = dem.get("planes", [])
    need(len(planes) == 1 and [float(x) for x in planes[0]["normal"]] == [1.0],
         "needs one plane with normal [1]")
    p = dem["particles"][0]
    need(float(p["velocity"][0]) == 0.0, "the closed form starts from rest")
    return dict(
        m=float(p["mass"]), k=float(p["stiffness"]), r=float(p["radius"]),
        zeta=float(dem["contact"]["damping_ratio"]), g=-float(scene["gravity"][0]),
        y0=float(p["position"][0]), t_end=float(scene["time"]["end"]),
        plane=float(planes[0]["point"][0]),
        integrator=dem.get("integrator", "abm4"), name=p["name"])


def exact_state(events, P, t):
    """Closed-form (y, v) at time t (drop_closed_form.position, plus velocity)."""
    g, r, plane = P["g"], P["r"], P["plane"]
    t_start, y_start = 0.0, P["y0"]
    for e in events:
        if t < e["t_impact"]:
            dt = t - t_start
            return y_start - 0.5 * g * dt * dt, -g * dt
        end = e["t_impact"] + (e["duration"] if e["duration"] is not None else math.inf)
        if t < end:
            c = cf.Contact(P["m"], P["k"], P["zeta"], g, e["v_impact"])
            tau = t - e["t_impact"]
            return plane + r - c.d(tau), -c.dd(tau)
        if "t_apex" not in e:
            break
        t_start, y_start = e["t_apex"], e["apex"]
        if t < t_start:
            dt = t - t_start
            return y_start - 0.5 * g * dt * dt, -g * dt
    dt = t - t_start
    return y_start - 0.5 * g * dt * dt, -g * dt


def exact_series(events, P, t):
    ys, vs = zip(*(exact_state(events, P, float(ti)) for ti in t))
    return np.array(ys), np.array(vs)


# ---- estimators on sampled (t, y, v) -------------------------------------------
def _hermite(t, y, v, i):
    """Cubic through (y, v) at samples i and i+1, as coefficients in tau = t - t[i]."""
    h = t[i + 1] - t[i]
    dy = (y[i + 1] - y[i]) / h
    a2 = (3.0 * dy - 2.0 * v[i] - v[i + 1]) / h
    a3 = (v[i] + v[i + 1] - 2.0 * dy) / (h * h)
    return np.array([y[i], v[i], a2, a3]), h


def _poly(c, tau):
    return c[0] + tau * (c[1] + tau * (c[2] + tau * c[3]))


def _roots_in(coeffs_low_first, h):
    roots = np.roots(coeffs_low_first[::-1]) if np.any(coeffs_low_first[1:] != 0) else []
    eps = 1e-9 * h
    return [float(z.real) for z in np.atleast_1d(roots)
            if abs(z.imag) <= 1e-9 * h and -eps <= z.real <= h + eps]


def _flight_crossing(t, y, v, i, level, g, forward):
    """Time where the free-flight parabola through sample i (y'' = -g) meets
    level: the next such time (forward) or the previous one."""
    disc = v[i] * v[i] + 2.0 * g * (y[i] - level)
    if disc < 0.0:
        return math.nan
    root = math.sqrt(disc)
    return t[i] + ((v[i] + root) if forward else (v[i] - root)) / g


def _min_hermite(t, y, v, lo, hi):
    """Minimum of the polynomial of degree 2n-1 through (y, v) at the n samples
    lo..hi (the samples all inside one contact, where y is smooth)."""
    j = lo + int(np.argmin(y[lo:hi + 1]))
    h = t[j + 1] - t[j] if j + 1 < len(t) else t[j] - t[j - 1]
    s = (t[lo:hi + 1] - t[j]) / h
    deg = 2 * len(s)
    A, b = [], []
    for si, yi, vi in zip(s, y[lo:hi + 1], v[lo:hi + 1]):
        A.append([si ** p for p in range(deg)])
        b.append(yi)
        A.append([p * si ** (p - 1) if p else 0.0 for p in range(deg)])
        b.append(vi * h)
    c = np.linalg.solve(np.array(A), np.array(b))
    dc = np.array([p * c[p] for p in range(1, deg)])  # derivative, low first
    roots = np.roots(dc[::-1])
    cands = [y[j]] + [float(np.polyval(c[::-1], z.real)) for z in roots
                      if abs(z.imag) < 1e-9 and max(s[0], -1.0) <= z.real <= min(s[-1], 1.0)]
    return min(cands)


def _extremum(t, y, v, j, kind):
    """Refined extremum near sample j: kind = 'max' (v goes + to -) or 'min'."""
    sign = 1.0 if kind == "max" else -1.0
    for i in (j - 1, j):
        if 0 <= i < len(t) - 1 and sign * v[i] >= 0.0 and sign * v[i + 1] <= 0.0:
            c, h = _hermite(t, y, v, i)
            roots = _roots_in(np.array([c[1], 2.0 * c[2], 3.0 * c[3], 0.0]), h)
            cands = [y[i], y[i + 1]] + [_poly(c, tau) for tau in roots]
            return max(cands) if kind == "max" else min(cands)
    return math.nan  # extremum at the edge of the data: not measured


def measure(t, y, v, r, g, plane=0.0):
    """Contacts (start, end, max overlap) and apexes after each contact."""
    level = plane + r
    inside = y < level
    idx = np.flatnonzero(np.diff(inside.astype(np.int8)))
    starts = [i + 1 for i in idx if not inside[i]]
    ends = [i for i in idx if inside[i]]
    if inside[0]:
        starts = [0] + starts
    if inside[-1]:
        ends = ends + [len(t) - 1]
    contacts = []
    for n, (i0, i1) in enumerate(zip(starts, ends)):
        t_in = _flight_crossing(t, y, v, i0 - 1, level, g, True) if i0 > 0 else math.nan
        t_out = _flight_crossing(t, y, v, i1 + 1, level, g, False) if i1 < len(t) - 1 else math.nan
        j = i0 + int(np.argmin(y[i0:i1 + 1]))
        if i0 < j < i1:  # up to five samples around the minimum, all in contact
            overlap = level - _min_hermite(t, y, v, max(i0, j - 2), min(i1, j + 2))
        else:
            overlap = level - _extremum(t, y, v, j, "min")
        # apex: max of y between this contact and the next one (or the end)
        a0 = i1
        a1 = starts[n + 1] if n + 1 < len(starts) else len(t) - 1
        apex = math.nan
        if a1 > a0:
            ja = a0 + int(np.argmax(y[a0:a1 + 1]))
            apex = _extremum(t, y, v, ja, "max")
        contacts.append(dict(t_in=t_in, t_out=t_out, duration=t_out - t_in,
                             max_overlap=overlap, apex=apex))
    return contacts


def _rel(a, b):
    return (a - b) / b if b != 0 else math.nan


def errors(contacts, events):
    """Signed relative errors of apex, max overlap and duration, contacts 1..N."""
    out = {}
    for n in range(N_EVENTS):
        e = events[n] if n < len(events) else None
        c = contacts[n] if n < len(contacts) else None
        for key in ("apex", "max_overlap", "duration"):
            ok = e is not None and c is not None and e.get(key) is not None
            out[f"{key}_{n + 1}"] = _rel(c[key], e[key]) if ok else math.nan
    return out


def _worst(vals):
    vals = [x for x in vals if not math.isnan(x)]
    return max(vals, key=abs) if vals else math.nan


# ---- the handler ---------------------------------------------------------------
def analyse(runs, out_dir, plt):
    """runs: list of report.Run for this case. Returns the tables and figures."""
    by_k = {}
    for run in runs:
        P = parameters(run.scene, run.name)
        run.params = P
        by_k.setdefault(P["k"], []).append(run)
    ks = sorted(by_k)

    rows, ref_rows, long_rows = [], [], []
    series = {}  # k -> dict(exact events, per integrator (t, y, yex))
    for k in ks:
        P0 = by_k[k][0].params
        events = cf.bounces(P0["m"], k, P0["r"], P0["zeta"], P0["g"], P0["y0"], P0["t_end"], P0["plane"])
        series[k] = dict(events=events, P=P0, runs={})
        ref_rows.append([_k(k)] + [_fmt(events[n]["apex"], "f6") for n in range(N_EVENTS)]
                        + [_fmt(events[0]["max_overlap"], "f6"), _fmt(events[0]["duration"], "f6"),
                           _fmt(events[0]["t_impact"], "f6")])
        floor_done = False
        for run in sorted(by_k[k], key=lambda r: r.params["integrator"]):
            P = run.params
            for key in ("m", "r", "zeta", "g", "y0", "plane", "t_end"):
                if P[key] != P0[key]:
                    raise ValueError(f"{run.name}: {key} differs from the other k={k:g} runs")
            t, y, v = run.col("t"), run.col(run.probe("position")), run.col(run.probe("velocity"))
            yex, vex = exact_series(events, P, t)
            series[k]["runs"][P["integrator"]] = (t, y, yex)
            if not floor_done:
                floor = errors(measure(t, yex, vex, P["r"], P["g"], P["plane"]), events)
                floor_row = _row(k, "(sampling floor)", floor, 0.0)
                floor_done = True
            err = errors(measure(t, y, v, P["r"], P["g"], P["plane"]), events)
            dmax = float(np.max(np.abs(y - yex)))
            rows.append(_row(k, P["integrator"], err, dmax))
            for key, val in err.items():
                long_rows.append([CASE, run.name, k, P["integrator"], f"{key}_rel_err", val])
            long_rows.append([CASE, run.name, k, P["integrator"], "max_abs_y_err_m", dmax])
        rows.append(floor_row)
        for key, val in floor.items():
            long_rows.append([CASE, f"v1_k{_k(k)}_floor", k, "sampling_floor", f"{key}_rel_err", val])

    tables = [
        dict(title="V1 drop test: closed-form reference (contact 1 for overlap, duration, impact time)",
             columns=["k [N/m]", "apex 1 [m]", "apex 2 [m]", "apex 3 [m]", "max overlap [m]",
                      "duration [s]", "impact [s]"],
             rows=ref_rows),
        dict(title="V1 drop test: signed relative errors (simulated - exact)/exact; "
                   "overlap and duration: the largest of contacts 1-3; max|y-y_exact| in m over 0-6 s",
             columns=["k [N/m]", "integrator", "apex 1", "apex 2", "apex 3", "max overlap",
                      "contact duration", "max|y-y_exact| [m]"],
             rows=[r[0] for r in rows],
             note=(f"Measured from the CSVs (output every {_every(runs)} s): contact start/end from the free-flight parabola "
                   "through the sample next to the crossing; max overlap and apex from the Hermite "
                   "polynomial through (y, v) at the samples around the extremum. (sampling floor): the "
                   "same estimators on the closed form sampled at the same times.")),
    ]
    figures = _plots(series, out_dir, plt)
    return tables, long_rows, figures


def _k(k):
    """1e3, 1e4, ... (or the plain number when k is not a power of ten)."""
    e = round(math.log10(k)) if k > 0 else 0
    return f"1e{e}" if k == 10.0 ** e else f"{k:g}"


def _every(runs):
    return ", ".join(sorted({f"{float(r.scene['output']['every']):g}" for r in runs}))


def _fmt(x, how="e"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    return f"{x:.6f}" if how == "f6" else f"{x:+.2e}"


def _row(k, label, err, dmax):
    cells = [_k(k), label] + [_fmt(err[f"apex_{n}"]) for n in range(1, N_EVENTS + 1)]
    cells += [_fmt(_worst([err[f"max_overlap_{n}"] for n in range(1, N_EVENTS + 1)])),
              _fmt(_worst([err[f"duration_{n}"] for n in range(1, N_EVENTS + 1)])),
              f"{dmax:.2e}"]
    return (cells,)


def _plots(series, out_dir, plt):
    ks = sorted(series)
    files = []
    # fig 6 equivalent: trajectories with the closed form, plus a zoom on contact 1
    fig, axes = plt.subplots(len(ks), 2, figsize=(12, 3.2 * len(ks)), squeeze=False,
                             gridspec_kw=dict(width_ratios=[2.2, 1]))
    for row, k in enumerate(ks):
        s = series[k]
        P, events = s["P"], s["events"]
        ax = axes[row][0]
        t, y, _ = s["runs"].get("abm4") or next(iter(s["runs"].values()))
        tf = np.linspace(0.0, P["t_end"], 12001)
        yf, _ = exact_series(events, P, tf)
        ax.plot(t, y, "-", color="C0", lw=1.6, label="xfdem, abm4")
        ax.plot(tf, yf, "--", color="k", lw=0.9, label="closed form")
        ax.axhline(P["plane"] + P["r"], color="0.6", lw=0.6, ls=":", label="y = r (contact)")
        ax.set_ylabel("centre height y [m]")
        ax.set_title(f"V1 drop test, k = {_k(k)} N/m")
        ax.set_xlim(0, P["t_end"])
        ax.legend(loc="upper right", fontsize=8)
        # zoom on the first contact
        ax = axes[row][1]
        e = events[0]
        t0, t1 = e["t_impact"] - 0.3 * e["duration"], e["t_impact"] + 1.3 * e["duration"]
        tz = np.linspace(t0, t1, 2001)
        yz, _ = exact_series(events, P, tz)
        ax.plot(tz, yz, "-", color="k", lw=0.9, label="closed form")
        for n, (integ, (t_, y_, _)) in enumerate(sorted(s["runs"].items())):
            m = np.flatnonzero((t_ >= t0) & (t_ <= t1))
            m = m[::max(1, len(m) // 40)]  # at most ~40 markers
            ax.plot(t_[m], y_[m], "o", ms=3.5 - 1.5 * n, mfc="none" if n == 0 else None,
                    color=f"C{n}", label=f"xfdem, {integ}")
        ax.axhline(P["plane"] + P["r"], color="0.6", lw=0.6, ls=":")
        ax.set_title(f"contact 1, k = {_k(k)} N/m")
        ax.legend(loc="lower right", fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.tight_layout()
    path = f"{out_dir}/v1_fig6_trajectories.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    files.append(path)

    # error against the closed form, log axis, abm4 vs abm4_events
    fig, axes = plt.subplots(len(ks), 1, figsize=(10, 2.8 * len(ks)), squeeze=False, sharex=True)
    for row, k in enumerate(ks):
        ax = axes[row][0]
        for n, (integ, (t, y, yex)) in enumerate(sorted(series[k]["runs"].items())):
            err = np.abs(y - yex)
            ax.semilogy(t, np.maximum(err, 1e-16), "-", color=f"C{n}", lw=0.9, label=integ)
        for e in series[k]["events"]:
            ax.axvline(e["t_impact"], color="0.8", lw=0.5, zorder=0)
        ax.set_ylim(1e-16, None)
        ax.set_ylabel("|y - y_exact| [m]")
        ax.set_title(f"V1, k = {_k(k)} N/m (grey: closed-form impact times)")
        ax.legend(loc="lower right", fontsize=8)
    axes[-1][0].set_xlabel("t [s]")
    fig.tight_layout()
    path = f"{out_dir}/v1_error.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    files.append(path)
    return files
