"""Closed-form solution of the V1 drop test (scenes.md): a sphere falling on a
rigid plane under gravity, linear spring-dashpot contact with damping ratio zeta.

Free flight is a parabola. In contact the overlap d = r - y obeys
    d'' + 2 zeta w d' + w^2 d = g,   w^2 = k/m,
a damped oscillator about the static overlap g/w^2, solved exactly. The contact
ends when the overlap returns to zero (law `linear`: the dashpot may pull); if it
never does, the sphere stays in contact and settles. Event times are found by
bisection on the closed-form expressions, to ~1e-15 s.
"""
import math


def _bisect(f, lo, hi, iters=200):
    flo = f(lo)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo <= 1e-16 * max(1.0, abs(hi)):
            break
    return 0.5 * (lo + hi)


class Contact:
    """Overlap d(t) from d(0)=0, d'(0)=v_in (>0) for the damped oscillator."""

    def __init__(self, m, k, zeta, g, v_in):
        self.w = math.sqrt(k / m)
        self.zeta = zeta
        self.wd = self.w * math.sqrt(1.0 - zeta * zeta)
        self.ds = g / self.w ** 2
        self.A = -self.ds
        self.B = (v_in + zeta * self.w * self.A) / self.wd

    def d(self, t):
        e = math.exp(-self.zeta * self.w * t)
        return self.ds + e * (self.A * math.cos(self.wd * t) + self.B * math.sin(self.wd * t))

    def dd(self, t):
        e = math.exp(-self.zeta * self.w * t)
        c, s = math.cos(self.wd * t), math.sin(self.wd * t)
        a = self.A * c + self.B * s
        b = -self.A * self.wd * s + self.B * self.wd * c
        return e * (b - self.zeta * self.w * a)

    def end(self):
        """First t > 0 with d(t) = 0 after the overlap grew, or None (stays in contact)."""
        # The overlap rises, peaks, and either returns to zero within about one
        # damped half-period or never does; scan finely, then bisect the bracket.
        period = 2.0 * math.pi / self.wd
        samples = 4000
        t_prev = 0.0
        for n in range(1, 4 * samples):
            t = n * period / samples
            if self.d(t) <= 0.0:
                return _bisect(self.d, t_prev, t)
            t_prev = t
        return None


def bounces(m, k, r, zeta, g, y0, t_end, plane=0.0):
    """Events of the drop test until t_end. Returns a list of dicts with
    impact time, impact speed, max overlap, contact duration, exit speed, apex
    time and apex height (centre), in order; the last one may be unfinished."""
    out = []
    t, y, v = 0.0, y0, 0.0
    while t < t_end:
        # free flight until y = plane + r
        h = y - (plane + r)
        if h < 0:
            break
        t_fall = (v + math.sqrt(v * v + 2 * g * h)) / g
        t_hit = t + t_fall
        v_in = g * t_fall - v  # speed downwards at impact
        if t_hit > t_end:
            break
        c = Contact(m, k, zeta, g, v_in)
        # maximum overlap: first zero of d'
        t_max = _bisect(c.dd, 1e-14, math.pi / c.wd)
        dur = c.end()
        rec = dict(t_impact=t_hit, v_impact=v_in, max_overlap=c.d(t_max), t_max=t_hit + t_max, duration=dur)
        if dur is None:
            rec["settled"] = True
            out.append(rec)
            break
        v_out = -c.dd(dur)  # upwards
        rec["v_exit"] = v_out
        rec["t_apex"] = t_hit + dur + v_out / g
        rec["apex"] = plane + r + v_out * v_out / (2 * g)
        out.append(rec)
        t, y, v = t_hit + dur, plane + r, v_out
        # next: rising then falling; set state at apex
        t, y, v = rec["t_apex"], rec["apex"], 0.0
    return out


def position(events, m, k, r, zeta, g, y0, t, plane=0.0):
    """Centre height at time t from the event list (for plots)."""
    t_start, y_start = 0.0, y0
    for e in events:
        if t < e["t_impact"]:
            dt = t - t_start
            return y_start - 0.5 * g * dt * dt
        end = e["t_impact"] + (e["duration"] if e["duration"] is not None else float("inf"))
        if t < end:
            c = Contact(m, k, zeta, g, e["v_impact"])
            return plane + r - c.d(t - e["t_impact"])
        if "t_apex" not in e:
            break
        t_start, y_start = e["t_apex"], e["apex"]
        if t < t_start:
            dt = t_start - t
            return y_start - 0.5 * g * dt * dt
    dt = t - t_start
    return y_start - 0.5 * g * dt * dt
