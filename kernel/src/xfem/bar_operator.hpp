// The bar as seen by the Newmark integrator: one operation, implicit_solve().
// Private to the kernel.
#pragma once
#include "xfdem/bar.hpp"

namespace xfdem::detail {

/// gap = Σ gap_coeff[i] x[gap_dof[i]].
inline double bar_gap_of(const BarModel& m, const double* x) {
  double g = 0.0;
  for (int i = 0; i < m.gap_terms; ++i) g += m.gap_coeff[i] * x[m.gap_dof[i]];
  return g;
}

class BarOperator {
 public:
  BarOperator(const BarModel& model, BarWorkspace& workspace, double extra_tip_force, std::int32_t& interface_closed)
      : m_(model), ws_(workspace), extra_tip_force_(extra_tip_force), closed_(interface_closed) {}
  /// A substep of a unilateral interface: the active set `interface_closed` is
  /// held (no iteration), and a step's solve uses `substep_factor`, which the
  /// caller factored for the substep's (fac0, fac1) and that active set.
  BarOperator(const BarModel& model, BarWorkspace& workspace, double extra_tip_force, std::int32_t& interface_closed,
              const xfem::BandLdlt& substep_factor)
      : m_(model),
        ws_(workspace),
        extra_tip_force_(extra_tip_force),
        closed_(interface_closed),
        substep_factor_(&substep_factor) {}

  /// The step's response to the tip force alone: the tip load is left out
  /// (BarModel::tip_response_*).
  enum Homogeneous { homogeneous };
  BarOperator(const BarModel& model, BarWorkspace& workspace, double extra_tip_force, std::int32_t& interface_closed,
              Homogeneous)
      : m_(model), ws_(workspace), extra_tip_force_(extra_tip_force), closed_(interface_closed), homogeneous_(true) {}

  [[nodiscard]] int size() const { return m_.dofs; }

  /// Solves (M + fac1 C + fac0 K) k = f(t) − C v − K x for k, with (fac0, fac1)
  /// either (0, 0) (the initial acceleration: M k = f − C v − K x) or the
  /// model's (βΔt², γΔt), whose matrices were factored at build. The unilateral
  /// interface picks its active set here: closed iff the gap at the solution,
  /// x + fac0 k, is negative (unless the operator holds a substep's set).
  StepStatus implicit_solve(double fac0, double fac1, double t, const double* x, const double* v, double* k) const;

 private:
  const BarModel& m_;
  BarWorkspace& ws_;
  double extra_tip_force_;
  std::int32_t& closed_;
  const xfem::BandLdlt* substep_factor_ = nullptr;
  bool homogeneous_ = false;
};

/// Writes M + fac1·C + fac0·(K + [closed] k g gᵀ) into `out`, which has the
/// profile of M. The build's effective matrices and a substep's come from here.
void assemble_effective(const BarModel& m, double fac0, double fac1, bool closed, xfem::SymmetricBand& out);

}  // namespace xfdem::detail

