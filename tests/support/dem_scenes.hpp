// Small scenes the DEM tests share, and measurement helpers.
#pragma once
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "support/drop_closed_form.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {

/// One particle (m = 1, r = 0.05, k = 1e6) resting on a plane through the
/// origin tilted by theta (normal (−sin θ, cos θ)), pressed in by its static
/// overlap m g cos θ / k (g = 9.81) so that no normal oscillation starts.
/// Verlet, dt = 1e-5 s.
template <int D>
inline DemDesc<D> incline(double theta, double mu, double rolling, double zeta,
                          DemIntegrator integrator = DemIntegrator::verlet) {
  const double g = 9.81;
  DemDesc<D> d;
  d.dt = 1e-5;
  d.damping_ratio = zeta;
  d.friction = mu;
  d.rolling_friction = rolling;
  d.integrator = integrator;
  d.gravity[1] = -g;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  const double height = p.radius - p.mass * g * std::cos(theta) / p.stiffness;
  p.position[0] = -std::sin(theta) * height;
  p.position[1] = std::cos(theta) * height;
  d.particles.push_back(p);
  PlaneDesc<D> plane;
  plane.normal[0] = -std::sin(theta);
  plane.normal[1] = std::cos(theta);
  d.planes.push_back(plane);
  return d;
}

/// Least-squares slope of y against x.
inline double least_squares_slope(const std::vector<std::pair<double, double>>& points) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(points.size());
  for (const auto& [x, y] : points) {
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// Observed order: the least-squares slope of log(error) against log(dt).
inline double observed_order(const std::vector<double>& dts, const std::vector<double>& errors) {
  std::vector<std::pair<double, double>> points;
  for (std::size_t k = 0; k < dts.size(); ++k) points.emplace_back(std::log(dts[k]), std::log(errors[k]));
  return least_squares_slope(points);
}

/// The spin about z of particle 0 (2D: the only component; 3D: component 2).
template <int D>
double spin_z(const DemState<D>& s) {
  return s.w[D == 2 ? 0 : 2][0];
}

/// I / (m r²) of a disk (2D) or a sphere (3D).
template <int D>
constexpr double inertia_factor() {
  return D == 2 ? 0.5 : 0.4;
}

/// The V1 drop test as a 1D scene (plane at 0, normal up).
inline DemDesc<1> drop_scene(const DropParameters& p, DemIntegrator integrator, double dt) {
  DemDesc<1> d;
  d.gravity = {-p.g};
  d.law = ContactLaw::linear;
  d.damping_ratio = p.zeta;
  d.integrator = integrator;
  d.dt = dt;
  d.particles.push_back({p.mass, p.radius, p.stiffness, {p.y0}, {0.0}});
  d.planes.push_back({{0.0}, {1.0}});
  return d;
}

/// Whether `p` overlaps one of `placed` by more than the smaller radius: a
/// start build_dem refuses. Random clouds redraw such a position (with a 1 %
/// margin, so that round-off cannot tip a pair over).
template <int D>
bool starts_too_deep(const std::vector<ParticleDesc<D>>& placed, const ParticleDesc<D>& p) {
  for (const auto& q : placed) {
    double dist2 = 0;
    for (int k = 0; k < D; ++k) dist2 += (p.position[k] - q.position[k]) * (p.position[k] - q.position[k]);
    const double closest = 1.01 * std::max(p.radius, q.radius);  // overlap r_p + r_q − d ≤ the smaller radius
    if (dist2 < closest * closest) return true;
  }
  return false;
}

/// A sample of a 1D trajectory.
struct Sample {
  double t, y, v;
};

/// Cubic Hermite interpolant through two samples, evaluated at t.
inline double hermite(const Sample& a, const Sample& b, double t) {
  const double h = b.t - a.t, s = (t - a.t) / h;
  const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s), h01 = s * s * (3 - 2 * s),
               h11 = s * s * (s - 1);
  return h00 * a.y + h10 * h * a.v + h01 * b.y + h11 * h * b.v;
}

/// Time at which the Hermite interpolant crosses `level` between a and b.
inline double crossing(const Sample& a, const Sample& b, double level) {
  return bisect([&](double t) { return hermite(a, b, t) - level; }, a.t, b.t);
}

/// Vertex of the parabola through three equally spaced samples (exact for
/// free flight, O(h^3) elsewhere): returns the extreme value.
inline double parabola_extreme(double y0, double y1, double y2) {
  const double denom = y0 - 2 * y1 + y2;
  if (denom == 0) return y1;
  const double s = 0.5 * (y0 - y2) / denom;  // offset of the vertex from the middle, in steps
  return y1 - 0.25 * (y0 - y2) * s;
}

/// Contact-by-contact measurements of a simulated drop.
struct MeasuredBounce {
  double t_impact = 0, t_release = 0, max_overlap = 0, apex_after = NAN;
};

/// Runs a 1D drop world to t_end and measures each contact: touch-down and
/// release times (Hermite-interpolated crossings of y = r), the maximum
/// overlap and the apex of the following flight (parabola through the samples
/// around the extreme).
inline std::vector<MeasuredBounce> measure_drop(DemWorld<1>& world, double radius, double t_end) {
  std::vector<Sample> samples;
  const auto steps = static_cast<long>(std::llround(t_end / world.model.dt));
  samples.reserve(static_cast<std::size_t>(steps) + 1);
  samples.push_back({0.0, world.state.x[0][0], world.state.v[0][0]});
  for (long n = 0; n < steps; ++n) {
    if (world.step() != StepStatus::ok) break;
    samples.push_back({world.state.time, world.state.x[0][0], world.state.v[0][0]});
  }
  std::vector<MeasuredBounce> out;
  MeasuredBounce* open = nullptr;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const bool was_in = samples[k - 1].y < radius, is_in = samples[k].y < radius;
    if (!was_in && is_in) {
      out.push_back({});
      open = &out.back();
      open->t_impact = crossing(samples[k - 1], samples[k], radius);
      open->t_release = NAN;
    } else if (was_in && !is_in && open) {
      open->t_release = crossing(samples[k - 1], samples[k], radius);
    }
    if (k + 1 < samples.size()) {
      const double y0 = samples[k - 1].y, y1 = samples[k].y, y2 = samples[k + 1].y;
      if (open && y1 <= y0 && y1 < y2 && is_in)  // deepest point of a contact
        open->max_overlap = std::max(open->max_overlap, radius - parabola_extreme(y0, y1, y2));
      if (open && y1 >= y0 && y1 > y2 && !is_in && std::isnan(open->apex_after))  // apex of the flight
        open->apex_after = parabola_extreme(y0, y1, y2);
    }
  }
  return out;
}

}  // namespace xfdem::testing
