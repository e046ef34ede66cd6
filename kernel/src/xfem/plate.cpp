#include "xfdem/plate.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace xfdem {

namespace {

using Code = BuildResult::Code;

/// Bound on the stored entries of one profile matrix (8 bytes each).
constexpr double kMaxProfileEntries = 5.0e7;

bool positive_finite(double x) { return std::isfinite(x) && x > 0.0; }

BuildResult fail(const char* format, double value) { return BuildResult::failure(Code::invalid_argument, format, value); }

const char* edge_name(PlateEdge e) {
  switch (e) {
    case PlateEdge::left: return "left";
    case PlateEdge::right: return "right";
    case PlateEdge::bottom: return "bottom";
    case PlateEdge::top: return "top";
  }
  return "?";
}

bool valid_edge(PlateEdge e) { return static_cast<unsigned>(e) <= 3u; }

// Node coordinate i of nc cells on [lo, hi]: the last node is exactly hi.
double node_coord(double lo, double hi, int i, int nc) { return i == nc ? hi : lo + (hi - lo) * i / nc; }

/// The cell holding coordinate x along one axis (on a cell edge: the smaller
/// index) and the parent coordinate in it; false when x is farther than 1e-9
/// of a cell outside [lo, hi].
bool locate_axis(double lo, double hi, int nc, double x, int& cell, double& xi) {
  const double h = (hi - lo) / nc;
  if (!(x >= lo - 1e-9 * h && x <= hi + 1e-9 * h)) return false;
  cell = std::clamp(static_cast<int>(std::ceil((x - lo) / h)) - 1, 0, nc - 1);
  const double x0 = node_coord(lo, hi, cell, nc), x1 = node_coord(lo, hi, cell + 1, nc);
  xi = std::clamp(2.0 * (x - x0) / (x1 - x0) - 1.0, -1.0, 1.0);
  return true;
}

// Parent coordinates of the element's nodes, counter-clockwise from the lower left.
constexpr double kXi[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEta[4] = {-1.0, -1.0, 1.0, 1.0};

/// Natural indices of cell (i, j)'s nodes, counter-clockwise from the lower left.
void cell_nodes(int nx, int i, int j, int out[4]) {
  out[0] = j * (nx + 1) + i;
  out[1] = out[0] + 1;
  out[2] = out[1] + nx + 1;
  out[3] = out[0] + nx + 1;
}

bool all_finite(const std::vector<double>& f) {
  double acc = 0.0;
  for (double x : f) acc += 0.0 * x;
  return acc == 0.0;
}

}  // namespace

// ---- element ----------------------------------------------------------------

void plate_element_matrices(double hx, double hy, const double elasticity[3][3], double thickness, double density,
                            double stiffness[64], double mass[64]) {
  using Mat8 = Eigen::Matrix<double, 8, 8>;
  Eigen::Matrix3d d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d(r, c) = elasticity[r][c];
  Mat8 k = Mat8::Zero(), m = Mat8::Zero();
  const double g = 1.0 / std::sqrt(3.0);
  const double det_j = 0.25 * hx * hy;  // weights 1
  for (int gp = 0; gp < 4; ++gp) {
    const double xi = gp == 0 || gp == 3 ? -g : g;
    const double eta = gp < 2 ? -g : g;
    Eigen::Matrix<double, 3, 8> b = Eigen::Matrix<double, 3, 8>::Zero();
    Eigen::Matrix<double, 4, 1> n;
    for (int a = 0; a < 4; ++a) {
      n(a) = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
      const double dx = 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * (2.0 / hx);
      const double dy = 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * (2.0 / hy);
      b(0, 2 * a) = dx;
      b(1, 2 * a + 1) = dy;
      b(2, 2 * a) = dy;
      b(2, 2 * a + 1) = dx;
    }
    k.noalias() += (thickness * det_j) * (b.transpose() * d * b);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 4; ++c) {
        const double mac = density * thickness * det_j * n(a) * n(c);
        m(2 * a, 2 * c) += mac;
        m(2 * a + 1, 2 * c + 1) += mac;
      }
  }
  // Exactly symmetric (the products above are, up to the order of a sum).
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) {
      stiffness[r * 8 + c] = r <= c ? k(r, c) : k(c, r);
      mass[r * 8 + c] = r <= c ? m(r, c) : m(c, r);
    }
}

// ---- the one operation the integrator needs ---------------------------------

namespace detail {

class PlateOperator {
 public:
  PlateOperator(const PlateModel& model, PlateWorkspace& workspace) : m_(model), ws_(workspace) {}
  [[nodiscard]] int size() const { return m_.dofs; }

  /// Solves (M + fac1 C + fac0 K) k = f(t) − C v − K x, with (fac0, fac1) either
  /// (0, 0) (M k = …: the initial acceleration) or the model's, factored at build.
  StepStatus implicit_solve(double fac0, double fac1, double t, const double* x, const double* v, double* k) const {
    (void)fac1;
    const int n = m_.dofs;
    double* shape = ws_.shape_end.data();
    const int slots = static_cast<int>(ws_.shape_end.size());
    for (int s = 0; s < slots; ++s) shape[s] = plate_load_shape(m_, s - 1, t);
    for (int i = 0; i < n; ++i) k[i] = m_.held_force[static_cast<std::size_t>(i)];
    const std::size_t entries = m_.load_dof.size();
    for (std::size_t e = 0; e < entries; ++e) k[m_.load_dof[e]] += m_.load_value[e] * shape[m_.load_of[e] + 1];
    m_.stiffness.subtract_product(x, k);
    for (std::size_t d = 0; d < m_.damper_dof.size(); ++d) k[m_.damper_dof[d]] -= m_.damper_coeff[d] * v[m_.damper_dof[d]];
    (fac0 == 0.0 ? m_.mass_factor : m_.effective_factor).solve(k);
    return StepStatus::ok;
  }

 private:
  const PlateModel& m_;
  PlateWorkspace& ws_;
};

}  // namespace detail

// ---- validation ---------------------------------------------------------------

BuildResult validate_plate(const PlateDesc& d) {
  for (int c = 0; c < 2; ++c) {
    if (!std::isfinite(d.min[c])) return fail("domain.min: must be finite, got %g", d.min[c]);
    if (!std::isfinite(d.max[c])) return fail("domain.max: must be finite, got %g", d.max[c]);
    if (!(d.max[c] - d.min[c] > 0.0))
      return BuildResult::failure(Code::invalid_argument, "domain.max: must exceed domain.min in %s (%g <= %g)",
                                  c == 0 ? "x" : "y", d.max[c], d.min[c]);
    if (d.cells[c] < 1)
      return BuildResult::failure(Code::invalid_argument, "cells: must be at least 1 in %s, got %d", c == 0 ? "x" : "y",
                                  d.cells[c]);
  }
  {
    // Each of the four profile matrices (M, K, and the factors) stores about
    // 2 nodes × (2 min(nx, ny) + 4) entries: bound it (a scene must not be
    // able to ask for terabytes).
    const double nodes = static_cast<double>(d.cells[0] + 1) * static_cast<double>(d.cells[1] + 1);
    const double entries = 2.0 * nodes * (2.0 * std::min(d.cells[0], d.cells[1]) + 4.0);
    if (entries > kMaxProfileEntries)
      return BuildResult::failure(Code::capacity,
                                  "cells: %d x %d needs about %.3g stored entries per matrix, more than this build's "
                                  "%.3g",
                                  d.cells[0], d.cells[1], entries, kMaxProfileEntries);
  }
  if (d.plane != PlateDesc::Plane::strain && d.plane != PlateDesc::Plane::stress)
    return BuildResult::failure(Code::invalid_argument, "plane: must be strain or stress, got %d", static_cast<int>(d.plane));
  if (!positive_finite(d.thickness)) return fail("thickness: must be positive and finite (m), got %g", d.thickness);
  if (!positive_finite(d.youngs_modulus))
    return fail("material.youngs_modulus: must be positive and finite (Pa), got %g", d.youngs_modulus);
  if (!std::isfinite(d.poisson_ratio) || d.poisson_ratio <= -1.0)
    return fail("material.poisson_ratio: must be finite and > -1, got %g", d.poisson_ratio);
  if (d.plane == PlateDesc::Plane::strain && d.poisson_ratio >= 0.5)
    return fail("material.poisson_ratio: must be < 0.5 in plane strain (incompressible material), got %g",
                d.poisson_ratio);
  if (d.plane == PlateDesc::Plane::stress && d.poisson_ratio > 0.5)
    return fail("material.poisson_ratio: must be <= 0.5, got %g", d.poisson_ratio);
  if (!positive_finite(d.density)) return fail("material.density: must be positive and finite (kg/m^3), got %g", d.density);
  for (int c = 0; c < 2; ++c)
    if (!std::isfinite(d.gravity[c])) return fail("gravity: must be finite, got %g", d.gravity[c]);
  const bool dynamic = d.analysis == PlateDesc::Analysis::dynamic;
  if (!dynamic && d.analysis != PlateDesc::Analysis::statics)
    return BuildResult::failure(Code::invalid_argument, "analysis: must be dynamic or static, got %d",
                                static_cast<int>(d.analysis));
  if (dynamic) {
    if (!positive_finite(d.dt)) return fail("dt: must be a positive finite time step (s), got %g", d.dt);
    if (!std::isfinite(d.gamma)) return fail("newmark.gamma: must be finite, got %g", d.gamma);
    if (!std::isfinite(d.beta)) return fail("newmark.beta: must be finite, got %g", d.beta);
    if (d.gamma < 0.5)
      return BuildResult::failure(Code::unstable_time_step, "newmark.gamma: must be >= 1/2 (stability), got %.17g",
                                  d.gamma);
    if (!xfem::NewmarkScheme{d.beta, d.gamma, d.dt}.unconditionally_stable())
      return BuildResult::failure(Code::unstable_time_step,
                                  "newmark.beta: must be >= (gamma + 1/2)^2 / 4 = %.17g for gamma = %.17g "
                                  "(unconditional stability), got %.17g",
                                  0.25 * (d.gamma + 0.5) * (d.gamma + 0.5), d.gamma, d.beta);
  }
  for (std::size_t s = 0; s < d.supports.size(); ++s) {
    const PlateSupport& sp = d.supports[s];
    if (!valid_edge(sp.edge))
      return BuildResult::failure(Code::invalid_argument, "supports.%zu.edge: must be left, right, bottom or top", s);
    if (sp.absorbing && !dynamic)
      return BuildResult::failure(Code::invalid_argument,
                                  "supports.%zu.absorbing: a static analysis has no dashpots (absorbing must be false)", s);
  }
  for (std::size_t p = 0; p < d.prescribed.size(); ++p)
    for (int c = 0; c < 2; ++c) {
      if (!std::isfinite(d.prescribed[p].at[c]))
        return BuildResult::failure(Code::invalid_argument, "prescribed.%zu.at: must be finite", p);
      if (!std::isfinite(d.prescribed[p].displacement[c]))
        return BuildResult::failure(Code::invalid_argument, "prescribed.%zu.displacement: must be finite", p);
    }
  for (std::size_t l = 0; l < d.loads.size(); ++l) {
    const PlateLoad& ld = d.loads[l];
    const char* what = ld.kind == PlateLoad::Kind::edge_traction ? "traction" : "force";
    if (ld.kind == PlateLoad::Kind::edge_traction) {
      if (!valid_edge(ld.edge))
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.edge: must be left, right, bottom or top", l);
    } else if (ld.kind == PlateLoad::Kind::point_force) {
      for (int c = 0; c < 2; ++c) {
        int cell = 0;
        double xi = 0.0;
        if (!locate_axis(d.min[c], d.max[c], d.cells[c], ld.at[c], cell, xi))
          return BuildResult::failure(Code::invalid_argument, "loads.%zu.at: (%g, %g) is outside the domain", l,
                                      ld.at[0], ld.at[1]);
      }
    } else {
      return BuildResult::failure(Code::invalid_argument, "loads.%zu: unknown kind %d", l, static_cast<int>(ld.kind));
    }
    for (int c = 0; c < 2; ++c)
      if (!std::isfinite(ld.value[c]))
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.%s: must be finite", l, what);
    switch (ld.shape) {
      case PlateLoadShape::none:
      case PlateLoadShape::step:
        if (ld.duration != 0.0)
          return BuildResult::failure(Code::invalid_argument,
                                      "loads.%zu.duration: only a half_sine load has a duration; must be 0, got %g", l,
                                      ld.duration);
        break;
      case PlateLoadShape::half_sine:
        if (!dynamic)
          return BuildResult::failure(Code::invalid_argument,
                                      "loads.%zu.shape: a static analysis has no time; half_sine needs analysis "
                                      "dynamic (use step)",
                                      l);
        if (!positive_finite(ld.duration))
          return BuildResult::failure(Code::invalid_argument, "loads.%zu.duration: must be positive and finite (s), got %g",
                                      l, ld.duration);
        break;
      default:
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.shape: must be none, step or half_sine", l);
    }
  }
  if (d.max_dofs < 0) return BuildResult::failure(Code::invalid_argument, "max_dofs: must be >= 0, got %d", d.max_dofs);
  if (BuildResult r = validate_energy_check(d.energy_check); !r.ok()) return r;
  return BuildResult::success();
}

// ---- build --------------------------------------------------------------------

BuildResult build_plate(const PlateDesc& d, PlateModel& model, PlateState& state, PlateWorkspace& workspace) {
  model = PlateModel{};
  state = PlateState{};
  workspace = PlateWorkspace{};
  if (BuildResult r = validate_plate(d); !r.ok()) return r;
  model.desc = d;
  const int nx = d.cells[0], ny = d.cells[1];
  const int nodes = (nx + 1) * (ny + 1);
  model.nodes = nodes;
  const double hx = (d.max[0] - d.min[0]) / nx, hy = (d.max[1] - d.min[1]) / ny;
  model.cell_size[0] = hx;
  model.cell_size[1] = hy;
  auto xs = [&](int i) { return node_coord(d.min[0], d.max[0], i, nx); };
  auto ys = [&](int j) { return node_coord(d.min[1], d.max[1], j, ny); };

  // ---- material -------------------------------------------------------------
  const double e = d.youngs_modulus, nu = d.poisson_ratio;
  double(&dm)[3][3] = model.elasticity;
  if (d.plane == PlateDesc::Plane::stress) {
    const double f = e / (1.0 - nu * nu);
    dm[0][0] = dm[1][1] = f;
    dm[0][1] = dm[1][0] = f * nu;
    dm[2][2] = f * 0.5 * (1.0 - nu);
  } else {
    const double f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    dm[0][0] = dm[1][1] = f * (1.0 - nu);
    dm[0][1] = dm[1][0] = f * nu;
    dm[2][2] = f * 0.5 * (1.0 - 2.0 * nu);
  }
  model.wave_speed[0] = std::sqrt(dm[0][0] / d.density);
  model.wave_speed[1] = std::sqrt(dm[2][2] / d.density);
  plate_element_matrices(hx, hy, dm, d.thickness, d.density, model.element_stiffness, model.element_mass);

  // ---- constraints ----------------------------------------------------------
  // Nodes of an edge, in order along it.
  auto edge_nodes = [&](PlateEdge edge, auto&& visit) {
    switch (edge) {
      case PlateEdge::left:
        for (int j = 0; j <= ny; ++j) visit(j * (nx + 1), ys(j));
        break;
      case PlateEdge::right:
        for (int j = 0; j <= ny; ++j) visit(j * (nx + 1) + nx, ys(j));
        break;
      case PlateEdge::bottom:
        for (int i = 0; i <= nx; ++i) visit(i, xs(i));
        break;
      case PlateEdge::top:
        for (int i = 0; i <= nx; ++i) visit(ny * (nx + 1) + i, xs(i));
        break;
    }
  };
  const auto n2 = static_cast<std::size_t>(2 * nodes);
  std::vector<int> held(n2, 0);  // 0 free, 1 support, 2 prescribed
  std::vector<int> held_by(n2, -1);
  model.node_held.assign(n2, 0.0);
  for (std::size_t s = 0; s < d.supports.size(); ++s)
    edge_nodes(d.supports[s].edge, [&](int n, double) {
      for (int c = 0; c < 2; ++c)
        if (d.supports[s].fix[c] && held[static_cast<std::size_t>(2 * n + c)] == 0) {
          held[static_cast<std::size_t>(2 * n + c)] = 1;
          held_by[static_cast<std::size_t>(2 * n + c)] = static_cast<int>(s);
        }
    });
  for (std::size_t p = 0; p < d.prescribed.size(); ++p) {
    const PlatePrescribed& pr = d.prescribed[p];
    const int i = static_cast<int>(std::lround((pr.at[0] - d.min[0]) / hx));
    const int j = static_cast<int>(std::lround((pr.at[1] - d.min[1]) / hy));
    if (i < 0 || i > nx || j < 0 || j > ny || std::fabs(pr.at[0] - xs(i)) > 1e-9 * hx ||
        std::fabs(pr.at[1] - ys(j)) > 1e-9 * hy)
      return BuildResult::failure(Code::invalid_argument,
                                  "prescribed.%zu.at: (%g, %g) is not a node of the mesh (within 1e-9 of a cell)", p,
                                  pr.at[0], pr.at[1]);
    const int n = j * (nx + 1) + i;
    for (int c = 0; c < 2; ++c) {
      const auto k = static_cast<std::size_t>(2 * n + c);
      if (held[k] == 1 && pr.displacement[c] != 0.0)
        return BuildResult::failure(Code::invalid_argument,
                                    "prescribed.%zu.displacement: the node at (%g, %g) is held at 0 in %s by "
                                    "supports.%d (edge %s)",
                                    p, pr.at[0], pr.at[1], c == 0 ? "x" : "y", held_by[k],
                                    edge_name(d.supports[static_cast<std::size_t>(held_by[k])].edge));
      if (held[k] == 2 && model.node_held[k] != pr.displacement[c])
        return BuildResult::failure(Code::invalid_argument,
                                    "prescribed.%zu.displacement: the node at (%g, %g) is already prescribed by "
                                    "prescribed.%d with another value",
                                    p, pr.at[0], pr.at[1], held_by[k]);
      if (held[k] == 0) {
        held[k] = 2;
        held_by[k] = static_cast<int>(p);
        model.node_held[k] = pr.displacement[c];
      }
    }
  }

  // ---- unknowns: node by node along the shorter side (a narrow profile) -----
  model.node_dof.assign(n2, -1);
  int next = 0;
  const bool rows = nx <= ny;
  for (int r = 0; r < nodes; ++r) {
    const int i = rows ? r % (nx + 1) : r / (ny + 1);
    const int j = rows ? r / (nx + 1) : r % (ny + 1);
    const int n = j * (nx + 1) + i;
    for (int c = 0; c < 2; ++c)
      if (held[static_cast<std::size_t>(2 * n + c)] == 0) model.node_dof[static_cast<std::size_t>(2 * n + c)] = next++;
  }
  model.dofs = next;
  if (d.max_dofs > 0 && model.dofs > d.max_dofs)
    return BuildResult::failure(Code::capacity, "max_dofs: the mesh needs %d unknowns, more than max_dofs = %d",
                                model.dofs, d.max_dofs);
  if (model.dofs == 0)
    return BuildResult::failure(Code::invalid_argument, "supports: every nodal displacement is held; nothing to solve");
  const int nd = model.dofs;
  const auto nds = static_cast<std::size_t>(nd);

  // ---- profile and assembly ---------------------------------------------------
  auto element_dofs = [&](int i, int j, int out[8]) {
    int en[4];
    cell_nodes(nx, i, j, en);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 2; ++c) out[2 * a + c] = model.node_dof[static_cast<std::size_t>(2 * en[a] + c)];
  };
  std::vector<int> first(nds);
  for (int k = 0; k < nd; ++k) first[static_cast<std::size_t>(k)] = k;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int ed[8];
      element_dofs(i, j, ed);
      int lowest = std::numeric_limits<int>::max();
      for (int a : ed)
        if (a >= 0) lowest = std::min(lowest, a);
      for (int a : ed)
        if (a >= 0) first[static_cast<std::size_t>(a)] = std::min(first[static_cast<std::size_t>(a)], lowest);
    }
  model.mass.resize(nd, first);
  model.stiffness.resize(nd, first);
  model.held_force.assign(nds, 0.0);
  model.node_mass.assign(static_cast<std::size_t>(nodes), 0.0);
  const double* ke = model.element_stiffness;
  const double* me = model.element_mass;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int ed[8], en[4];
      element_dofs(i, j, ed);
      cell_nodes(nx, i, j, en);
      for (int a = 0; a < 8; ++a) {
        const int ra = ed[a];
        if (ra < 0) continue;
        for (int b = 0; b <= a; ++b) {
          const int rb = ed[b];
          if (rb < 0) continue;
          model.stiffness.add(ra, rb, ke[a * 8 + b]);
          model.mass.add(ra, rb, me[a * 8 + b]);
        }
        for (int b = 0; b < 8; ++b)
          if (ed[b] < 0) {
            const double g = model.node_held[static_cast<std::size_t>(2 * en[b / 2] + b % 2)];
            if (g != 0.0) model.held_force[static_cast<std::size_t>(ra)] -= ke[a * 8 + b] * g;
          }
      }
      // ρ t ∫ N_a dA: the x rows' sums of the element mass.
      for (int a = 0; a < 4; ++a) {
        double s = 0.0;
        for (int b = 0; b < 4; ++b) s += me[(2 * a) * 8 + 2 * b];
        model.node_mass[static_cast<std::size_t>(en[a])] += s;
      }
    }
  model.mass_row_sums.assign(nds, 0.0);
  {
    const std::vector<double> ones(nds, 1.0);
    model.mass.multiply(ones.data(), model.mass_row_sums.data());
  }

  // ---- dashpots of absorbing edges --------------------------------------------
  {
    std::vector<double> c_dof(nds, 0.0);
    for (const PlateSupport& sp : d.supports) {
      if (!sp.absorbing) continue;
      const bool vertical = sp.edge == PlateEdge::left || sp.edge == PlateEdge::right;
      const int normal = vertical ? 0 : 1;
      const int count = vertical ? ny : nx;
      const double h = vertical ? hy : hx;
      int k = 0;
      edge_nodes(sp.edge, [&](int n, double) {
        const double share = (k == 0 || k == count ? 0.5 : 1.0) * h * d.thickness;
        ++k;
        for (int c = 0; c < 2; ++c) {
          const int dof = model.node_dof[static_cast<std::size_t>(2 * n + c)];
          if (dof < 0) continue;
          c_dof[static_cast<std::size_t>(dof)] += d.density * model.wave_speed[c == normal ? 0 : 1] * share;
        }
      });
    }
    for (int k = 0; k < nd; ++k)
      if (c_dof[static_cast<std::size_t>(k)] != 0.0) {
        model.damper_dof.push_back(k);
        model.damper_coeff.push_back(c_dof[static_cast<std::size_t>(k)]);
      }
  }

  // ---- loads, flattened (slot −1: self weight) ---------------------------------
  {
    std::vector<double> f(nds, 0.0);
    std::vector<char> touched(nds, 0);
    auto flush = [&](int load) {
      for (int k = 0; k < nd; ++k)
        if (touched[static_cast<std::size_t>(k)]) {
          model.load_dof.push_back(k);
          model.load_of.push_back(load);
          model.load_value.push_back(f[static_cast<std::size_t>(k)]);
          f[static_cast<std::size_t>(k)] = 0.0;
          touched[static_cast<std::size_t>(k)] = 0;
        }
    };
    auto add = [&](int n, int c, double value) {
      const int dof = model.node_dof[static_cast<std::size_t>(2 * n + c)];
      if (dof < 0) return;
      f[static_cast<std::size_t>(dof)] += value;
      touched[static_cast<std::size_t>(dof)] = 1;
    };
    if (d.self_weight) {
      for (int n = 0; n < nodes; ++n)
        for (int c = 0; c < 2; ++c)
          if (d.gravity[c] != 0.0) add(n, c, model.node_mass[static_cast<std::size_t>(n)] * d.gravity[c]);
      flush(-1);
    }
    for (std::size_t l = 0; l < d.loads.size(); ++l) {
      const PlateLoad& ld = d.loads[l];
      if (ld.kind == PlateLoad::Kind::edge_traction) {
        const bool vertical = ld.edge == PlateEdge::left || ld.edge == PlateEdge::right;
        const int count = vertical ? ny : nx;
        double prev = 0.0;
        int prev_node = -1, k = 0;
        edge_nodes(ld.edge, [&](int n, double s) {
          if (k > 0)
            for (int c = 0; c < 2; ++c) {
              const double half = 0.5 * (s - prev) * d.thickness * ld.value[c];
              add(prev_node, c, half);
              add(n, c, half);
            }
          (void)count;
          prev = s;
          prev_node = n;
          ++k;
        });
      } else {
        int ci = 0, cj = 0;
        double xi = 0.0, eta = 0.0;
        locate_axis(d.min[0], d.max[0], nx, ld.at[0], ci, xi);
        locate_axis(d.min[1], d.max[1], ny, ld.at[1], cj, eta);
        int en[4];
        cell_nodes(nx, ci, cj, en);
        for (int a = 0; a < 4; ++a) {
          const double na = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
          if (na == 0.0) continue;
          for (int c = 0; c < 2; ++c) add(en[a], c, na * ld.value[c]);
        }
      }
      flush(static_cast<int>(l));
    }
  }

  workspace.u_pred.assign(nds, 0.0);
  workspace.v_pred.assign(nds, 0.0);
  workspace.rhs.assign(nds, 0.0);
  workspace.shape_start.assign(d.loads.size() + 1, 0.0);
  workspace.shape_end.assign(d.loads.size() + 1, 0.0);
  workspace.load_u_start.assign(model.load_dof.size(), 0.0);
  workspace.damper_u_start.assign(model.damper_dof.size(), 0.0);
  workspace.damper_v_start.assign(model.damper_dof.size(), 0.0);
  state.u.assign(nds, 0.0);
  state.v.assign(nds, 0.0);
  state.a.assign(nds, 0.0);

  if (d.analysis == PlateDesc::Analysis::statics) {
    // K u = f with every load at its amplitude (shape step: 1; none: 0).
    if (!model.stiffness_factor.factor(model.stiffness) ||
        !(model.stiffness_factor.min_pivot() > 1e-12 * model.stiffness_factor.max_pivot()))
      return BuildResult::failure(Code::invalid_argument,
                                  "supports: the plate is not held against rigid motion (its stiffness is singular); "
                                  "a static analysis needs supports or prescribed nodes that stop %s",
                                  "translation and rotation");
    double* u = state.u.data();
    for (std::size_t k = 0; k < nds; ++k) u[k] = model.held_force[k];
    for (std::size_t e2 = 0; e2 < model.load_dof.size(); ++e2) {
      const int l = model.load_of[e2];
      const double s = l < 0 || d.loads[static_cast<std::size_t>(l)].shape == PlateLoadShape::step ? 1.0 : 0.0;
      u[model.load_dof[e2]] += model.load_value[e2] * s;
    }
    model.stiffness_factor.solve(u);
    model.built = true;
    if (!all_finite(state.u)) {
      model.built = false;
      return BuildResult::failure(Code::invalid_argument, "loads: the static solution is not finite");
    }
    state.energy = EnergyLedger{};
    return BuildResult::success();
  }

  // ---- dynamic: factor M and M + γΔt C + βΔt² K -------------------------------
  model.scheme = xfem::NewmarkScheme{d.beta, d.gamma, d.dt};
  if (!model.mass_factor.factor(model.mass))
    return BuildResult::failure(Code::invalid_argument, "cells: the mass matrix is not positive definite");
  {
    xfem::SymmetricBand eff = model.mass;
    const double fac0 = model.scheme.fac0(), fac1 = model.scheme.fac1();
    for (int i = 0; i < nd; ++i)
      for (int j = model.mass.first_column(i); j <= i; ++j) eff.add(i, j, fac0 * model.stiffness.get(i, j));
    for (std::size_t k = 0; k < model.damper_dof.size(); ++k)
      eff.add(model.damper_dof[k], model.damper_dof[k], fac1 * model.damper_coeff[k]);
    if (!model.effective_factor.factor(eff))
      return BuildResult::failure(Code::invalid_argument, "dt: the effective stiffness is not positive definite");
  }
  model.built = true;
  const StepStatus s = plate_initial_acceleration(model, state, workspace);
  if (s != StepStatus::ok) {
    model.built = false;
    return BuildResult::failure(Code::invalid_argument, "loads: the initial acceleration is not finite");
  }
  return BuildResult::success();
}

// ---- stepping -----------------------------------------------------------------

double plate_load_shape(const PlateModel& m, int load, double t) {
  if (load < 0) return 1.0;
  const PlateLoad& l = m.desc.loads[static_cast<std::size_t>(load)];
  switch (l.shape) {
    case PlateLoadShape::half_sine:
      return (t >= 0.0 && t <= l.duration) ? std::sin(std::numbers::pi * t / l.duration) : 0.0;
    case PlateLoadShape::step:
      return t >= 0.0 ? 1.0 : 0.0;
    case PlateLoadShape::none:
      break;
  }
  return 0.0;
}

StepStatus plate_initial_acceleration(const PlateModel& model, PlateState& state, PlateWorkspace& workspace) {
  if (!model.built || model.desc.analysis != PlateDesc::Analysis::dynamic) return StepStatus::not_built;
  const detail::PlateOperator op(model, workspace);
  op.implicit_solve(0.0, 0.0, state.time, state.u.data(), state.v.data(), state.a.data());
  const double e = plate_algorithmic_energy(model, state);
  energy_restart(state.energy, {e, e, e});
  StepStatus s = StepStatus::ok;
  if (!all_finite(state.u) || !all_finite(state.v) || !all_finite(state.a) || !std::isfinite(state.time))
    s |= StepStatus::non_finite;
  return s;
}

StepStatus plate_step(const PlateModel& model, PlateState& state, PlateWorkspace& ws) {
  if (!model.built || model.desc.analysis != PlateDesc::Analysis::dynamic) return StepStatus::not_built;
  const double t_n = static_cast<double>(state.step) * model.scheme.dt;
  const double t_next = static_cast<double>(state.step + 1) * model.scheme.dt;
  // Where the step starts, for the books of the work done over it.
  const std::size_t slots = ws.shape_start.size();
  for (std::size_t s = 0; s < slots; ++s) ws.shape_start[s] = plate_load_shape(model, static_cast<int>(s) - 1, t_n);
  const std::size_t entries = model.load_dof.size(), dampers = model.damper_dof.size();
  for (std::size_t e = 0; e < entries; ++e) ws.load_u_start[e] = state.u[static_cast<std::size_t>(model.load_dof[e])];
  for (std::size_t k = 0; k < dampers; ++k) {
    ws.damper_u_start[k] = state.u[static_cast<std::size_t>(model.damper_dof[k])];
    ws.damper_v_start[k] = state.v[static_cast<std::size_t>(model.damper_dof[k])];
  }
  const detail::PlateOperator op(model, ws);
  double net_force[2];
  StepStatus s = xfem::newmark_step(model.scheme, op, t_next, state.u.data(), state.v.data(), state.a.data(),
                                    ws.u_pred.data(), ws.v_pred.data(), model.mass_row_sums.data(), net_force);
  const double g = model.scheme.gamma;
  ws.last_external_impulse = model.scheme.dt * ((1.0 - g) * net_force[0] + g * net_force[1]);
  // Work with the scheme's weights (x_γ = (1 − γ) x_n + γ x_{n+1}): exact in
  // the discrete energy identity of a linear system.
  double work = 0.0;
  for (std::size_t e = 0; e < entries; ++e) {
    const auto slot = static_cast<std::size_t>(model.load_of[e] + 1);
    const double du = state.u[static_cast<std::size_t>(model.load_dof[e])] - ws.load_u_start[e];
    work += du * model.load_value[e] * ((1.0 - g) * ws.shape_start[slot] + g * ws.shape_end[slot]);
  }
  for (std::size_t k = 0; k < dampers; ++k) {
    const auto dof = static_cast<std::size_t>(model.damper_dof[k]);
    work -= model.damper_coeff[k] * (state.u[dof] - ws.damper_u_start[k]) *
            ((1.0 - g) * ws.damper_v_start[k] + g * state.v[dof]);
  }
  state.energy.work += work;
  state.step += 1;
  state.time = t_next;
  if (!all_finite(state.u) || !all_finite(state.v) || !all_finite(state.a) || !std::isfinite(state.energy.work))
    s |= StepStatus::non_finite;
  if (energy_check_due(model.desc.energy_check, state.step)) {
    const double energy = plate_algorithmic_energy(model, state);
    energy_check(state.energy, model.desc.energy_check, {energy, energy, energy});
  }
  if (state.energy.exceeded != 0) s |= StepStatus::energy_growth;
  return s;
}

// ---- probes -------------------------------------------------------------------

namespace {

/// The value of component c of natural node n in field f (held nodes: `held`
/// for displacements, 0 for rates).
inline double nodal(const PlateModel& m, const double* f, bool displacement, int n, int c) {
  const auto k = static_cast<std::size_t>(2 * n + c);
  const int dof = m.node_dof[k];
  return dof >= 0 ? f[dof] : (displacement ? m.node_held[k] : 0.0);
}

/// The cell (i, j) holding (x, y) and the parent coordinates there; false for
/// an unbuilt model or a point outside the domain.
bool locate(const PlateModel& m, double x, double y, int& i, int& j, double& xi, double& eta) {
  const PlateDesc& d = m.desc;
  return m.built && locate_axis(d.min[0], d.max[0], d.cells[0], x, i, xi) &&
         locate_axis(d.min[1], d.max[1], d.cells[1], y, j, eta);
}

double field_at(const PlateModel& m, const std::vector<double>& f, bool displacement, double x, double y, int c) {
  const PlateDesc& d = m.desc;
  int i = 0, j = 0;
  double xi = 0.0, eta = 0.0;
  if (c < 0 || c > 1 || !locate(m, x, y, i, j, xi, eta)) return std::numeric_limits<double>::quiet_NaN();
  int en[4];
  cell_nodes(d.cells[0], i, j, en);
  double s = 0.0;
  for (int a = 0; a < 4; ++a)
    s += 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]) * nodal(m, f.data(), displacement, en[a], c);
  return s;
}

/// ε = (ε_xx, ε_yy, γ_xy) at parent point (xi, eta) of cell (i, j).
void strain_at(const PlateModel& m, const double* u, int i, int j, double xi, double eta, double eps[3]) {
  int en[4];
  cell_nodes(m.desc.cells[0], i, j, en);
  eps[0] = eps[1] = eps[2] = 0.0;
  for (int a = 0; a < 4; ++a) {
    const double dx = 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * (2.0 / m.cell_size[0]);
    const double dy = 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * (2.0 / m.cell_size[1]);
    const double ux = nodal(m, u, true, en[a], 0), uy = nodal(m, u, true, en[a], 1);
    eps[0] += dx * ux;
    eps[1] += dy * uy;
    eps[2] += dy * ux + dx * uy;
  }
}

}  // namespace

double plate_displacement(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s.u, true, x, y, c);
}
double plate_velocity(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s.v, false, x, y, c);
}
double plate_acceleration(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s.a, false, x, y, c);
}

double plate_stress(const PlateModel& m, const PlateState& s, double x, double y, int component) {
  int i = 0, j = 0;
  double xi = 0.0, eta = 0.0;
  if (component < 0 || component > 2 || !locate(m, x, y, i, j, xi, eta)) return std::numeric_limits<double>::quiet_NaN();
  double eps[3];
  strain_at(m, s.u.data(), i, j, xi, eta, eps);
  const double(&dm)[3][3] = m.elasticity;
  return dm[component][0] * eps[0] + dm[component][1] * eps[1] + dm[component][2] * eps[2];
}

PlateEnergy plate_energy(const PlateModel& m, const PlateState& s) {
  PlateEnergy e;
  if (!m.built) return e;
  e.kinetic = 0.5 * m.mass.quadratic(s.v.data());
  // ½ t ∫ εᵀDε dA by the 2×2 Gauss rule (exact for the rectangle), from the
  // strains: a rigid motion has exactly zero strain, so no energy to lose in
  // the cancellation of uᵀKu.
  const double g = 1.0 / std::sqrt(3.0);
  const double w = 0.5 * m.desc.thickness * 0.25 * m.cell_size[0] * m.cell_size[1];
  const double(&dm)[3][3] = m.elasticity;
  double elastic = 0.0;
  for (int j = 0; j < m.desc.cells[1]; ++j)
    for (int i = 0; i < m.desc.cells[0]; ++i)
      for (int gp = 0; gp < 4; ++gp) {
        double eps[3];
        strain_at(m, s.u.data(), i, j, gp == 0 || gp == 3 ? -g : g, gp < 2 ? -g : g, eps);
        double q = 0.0;
        for (int r = 0; r < 3; ++r) q += eps[r] * (dm[r][0] * eps[0] + dm[r][1] * eps[1] + dm[r][2] * eps[2]);
        elastic += w * q;
      }
  e.elastic = elastic;
  if (m.desc.self_weight)
    for (int n = 0; n < m.nodes; ++n)
      for (int c = 0; c < 2; ++c)
        e.potential -= m.node_mass[static_cast<std::size_t>(n)] * m.desc.gravity[c] * nodal(m, s.u.data(), true, n, c);
  return e;
}

double plate_algorithmic_energy(const PlateModel& m, const PlateState& s) {
  if (!m.built) return 0.0;
  const PlateEnergy e = plate_energy(m, s);
  const xfem::NewmarkScheme& k = m.scheme;
  const double c = k.beta - 0.5 * k.gamma;
  return e.kinetic + e.elastic + (c == 0.0 ? 0.0 : 0.5 * k.dt * k.dt * c * m.mass.quadratic(s.a.data()));
}

double plate_momentum(const PlateModel& m, const PlateState& s, int component) {
  if (!m.built || component < 0 || component > 1) return std::numeric_limits<double>::quiet_NaN();
  double p = 0.0;
  for (int n = 0; n < m.nodes; ++n) p += m.node_mass[static_cast<std::size_t>(n)] * nodal(m, s.v.data(), false, n, component);
  return p;
}

}  // namespace xfdem
