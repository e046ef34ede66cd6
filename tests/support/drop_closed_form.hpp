// Closed-form solution of a sphere dropped on a rigid plane (the paper's V1):
// free flight under gravity, then while the overlap δ = r − y is positive
//   δ'' + 2ζω δ' + ω² δ = g,  ω² = k/m,
// a damped oscillator about the static overlap g/ω², solved exactly; the
// contact ends when δ returns to zero (law `linear`), or never (the sphere
// settles). Event times come from bisection on the exact expressions.
#pragma once
#include <cmath>
#include <optional>
#include <vector>

namespace xfdem::testing {

struct DropParameters {
  double mass = 1, radius = 0.1, stiffness = 1e4, zeta = 0.1, g = 9.81, y0 = 3.0;
};

/// Overlap after touch-down with impact speed v_in (> 0, downwards).
struct ContactArc {
  double w, zeta, wd, ds, A, B;
  ContactArc(const DropParameters& p, double v_in)
      : w(std::sqrt(p.stiffness / p.mass)),
        zeta(p.zeta),
        wd(w * std::sqrt(1 - p.zeta * p.zeta)),
        ds(p.g / (w * w)),
        A(-ds),
        B((v_in + p.zeta * w * A) / wd) {}
  [[nodiscard]] double overlap(double t) const {
    return ds + std::exp(-zeta * w * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
  }
  [[nodiscard]] double rate(double t) const {
    const double e = std::exp(-zeta * w * t), c = std::cos(wd * t), s = std::sin(wd * t);
    return e * ((-A * wd * s + B * wd * c) - zeta * w * (A * c + B * s));
  }
};

template <class F>
double bisect(F f, double lo, double hi) {
  const bool lo_positive = f(lo) > 0;
  for (int i = 0; i < 200 && hi - lo > 1e-17 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    ((f(mid) > 0) == lo_positive ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Bounce {
  double t_impact, v_impact, max_overlap;
  std::optional<double> duration;  ///< empty: the sphere never leaves
  double v_exit = 0, t_apex = 0, apex = 0;
};

/// Bounces that start before t_end.
inline std::vector<Bounce> drop_bounces(const DropParameters& p, double t_end) {
  std::vector<Bounce> out;
  double t = 0, y = p.y0;
  while (t < t_end) {
    const double h = y - p.radius;
    const double t_fall = std::sqrt(2 * h / p.g);
    Bounce b;
    b.t_impact = t + t_fall;
    b.v_impact = p.g * t_fall;
    if (b.t_impact > t_end) break;
    const ContactArc arc(p, b.v_impact);
    const double t_max = bisect([&](double s) { return arc.rate(s); }, 1e-15, M_PI / arc.wd);
    b.max_overlap = arc.overlap(t_max);
    // The overlap returns to zero within one damped period, or never.
    const double period = 2 * M_PI / arc.wd;
    double prev = 0;
    for (int n = 1; n <= 8000; ++n) {
      const double s = n * period / 4000;
      if (arc.overlap(s) <= 0) {
        b.duration = bisect([&](double q) { return arc.overlap(q); }, prev, s);
        break;
      }
      prev = s;
    }
    if (!b.duration) {
      out.push_back(b);
      break;
    }
    b.v_exit = -arc.rate(*b.duration);
    b.t_apex = b.t_impact + *b.duration + b.v_exit / p.g;
    b.apex = p.radius + b.v_exit * b.v_exit / (2 * p.g);
    out.push_back(b);
    t = b.t_apex;
    y = b.apex;
  }
  return out;
}

/// Centre height y(t) from the bounce list.
inline double drop_height(const DropParameters& p, const std::vector<Bounce>& bounces, double t) {
  double t0 = 0, y0 = p.y0;
  for (const Bounce& b : bounces) {
    if (t < b.t_impact) break;
    if (!b.duration || t < b.t_impact + *b.duration) return p.radius - ContactArc(p, b.v_impact).overlap(t - b.t_impact);
    t0 = b.t_apex;
    y0 = b.apex;
  }
  return y0 - 0.5 * p.g * (t - t0) * (t - t0);
}

}  // namespace xfdem::testing
