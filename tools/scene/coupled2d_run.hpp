// A coupled 2D scene (disks against a plate) as `xfdem run` and `xfdem_rt`
// step it: the kernel's Coupled2dWorld (whose step runs the energy balance
// check the scene key `energy_check` sets) and the energies its `energy`
// probe reads.
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

  /// One coupled step (coupled2d_step: the energy balance check included).
  /// No allocation.
  StepStatus step() { return world_.step(); }

  const Coupled2dWorld& world() const { return world_; }
  Coupled2dWorkspace& workspace() { return world_.workspace; }
  const EnergyLedger& ledger() const { return world_.state.energy; }

  /// The `energy` probe's parts of the state now (computed once per step):
  /// kinetic ½vᵀMv of the plate and the disks' (rotation included); elastic
  /// the plate's ½uᵀKu (crack penalties included), the disks' contacts with
  /// each other and with planes, and the disk–boundary contacts'; potential
  /// the disks' −m g·x and the plate's self weight −∫ρ g·u dV.
  const CoupledEnergy& energy() const;

 private:
  Coupled2dWorld world_;
  mutable std::vector<double> positions_;  ///< the boundary's vertices, scratch of the contact energy
  mutable DemEnergy dem_{};
  mutable PlateEnergy plate_{};
  mutable double boundary_ = 0;
  mutable CoupledEnergy energy_{};
  mutable std::int64_t energy_step_ = -1;
};

}  // namespace xfdem::scene
