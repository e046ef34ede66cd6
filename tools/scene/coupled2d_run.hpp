// A coupled 2D scene (disks against a plate) as `xfdem run` and `xfdem_rt`
// step it: the kernel's Coupled2dWorld, the energies its `energy` probe reads,
// and the energy balance check the scene key `energy_check` sets, which the
// kernel's coupled 2D step does not run (it turns its halves' checks off).
#pragma once
#include <cstdint>
#include <vector>

#include "scene/scene.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/energy_check.hpp"

namespace xfdem::scene {

class Coupled2dRun {
 public:
  /// Builds the world from the scene (coupled2d_desc; throws SceneError
  /// naming the key) and opens the energy books at its start.
  Coupled2dRun(const Scene& scene, ParallelFor parallel);

  /// One coupled step, then the energy books: every energy_check.interval
  /// steps the check E(t) − E0 − W(t) ≤ tolerance · max E_motion (+ round-off)
  /// (energy_check.hpp), with E the disks' energy (dem_energy: kinetic and
  /// rotational, contacts between disks and with planes, gravity's −m g·x),
  /// the disk–boundary contacts' (coupled2d_boundary_energy) and the plate's
  /// algorithmic energy Ê (plate_algorithmic_energy: ½vᵀMv + ½uᵀKu with the
  /// crack faces' penalties + ½Δt²(β − γ/2)aᵀMa), and W the work the plate's
  /// ledger books over its steps (loads and self weight, dampers, absorbing
  /// edges: PlateState::energy.work) plus the disks' (moving planes). The
  /// exchange is internal. From the first check that finds the energy above
  /// its books, every step says energy_growth. No allocation.
  StepStatus step();

  const Coupled2dWorld& world() const { return world_; }
  Coupled2dWorkspace& workspace() { return world_.workspace; }
  const EnergyLedger& ledger() const { return ledger_; }

  /// The `energy` probe's parts of the state now (computed once per step):
  /// kinetic ½vᵀMv of the plate and the disks' (rotation included); elastic
  /// the plate's ½uᵀKu (crack penalties included), the disks' contacts with
  /// each other and with planes, and the disk–boundary contacts'; potential
  /// the disks' −m g·x and the plate's self weight −∫ρ g·u dV.
  const CoupledEnergy& energy() const;

 private:
  /// What the check weighs (the plate's self weight is in W, not in E).
  EnergyTotals totals() const;

  Coupled2dWorld world_;
  EnergyCheck check_;
  EnergyLedger ledger_;
  double plate_work_start_ = 0, dem_work_start_ = 0;
  mutable std::vector<double> positions_;  ///< the boundary's vertices, scratch of the contact energy
  mutable DemEnergy dem_{};
  mutable PlateEnergy plate_{};
  mutable double boundary_ = 0;
  mutable CoupledEnergy energy_{};
  mutable std::int64_t energy_step_ = -1;
};

}  // namespace xfdem::scene
