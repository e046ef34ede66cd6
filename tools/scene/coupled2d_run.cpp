#include "scene/coupled2d_run.hpp"

#include <cmath>

namespace xfdem::scene {

Coupled2dRun::Coupled2dRun(const Scene& scene, ParallelFor parallel) : check_(scene.energy_check) {
  const BuildResult built = world_.build(coupled2d_desc(scene));
  if (!built.ok()) throw build_refusal(scene, Built::coupled, built);
  world_.workspace.dem.parallel = parallel;
  positions_.assign(2 * world_.model.boundary.vertices.size(), 0.0);
  plate_work_start_ = world_.state.plate.energy.work;
  dem_work_start_ = world_.state.dem.energy.work;
  energy_restart(ledger_, totals());
}

StepStatus Coupled2dRun::step() {
  StepStatus status = world_.step();
  const Coupled2dState& s = world_.state;
  if (energy_check_due(check_, s.step)) {
    ledger_.work = (s.plate.energy.work - plate_work_start_) + (s.dem.energy.work - dem_work_start_);
    energy_check(ledger_, check_, totals());
  }
  if (ledger_.exceeded != 0) status |= StepStatus::energy_growth;
  return status;
}

const CoupledEnergy& Coupled2dRun::energy() const {
  const Coupled2dModel& m = world_.model;
  const Coupled2dState& s = world_.state;
  if (energy_step_ != s.step) {
    dem_ = dem_energy(m.dem, s.dem);
    plate_ = plate_energy(m.plate, s.plate);
    boundary_ = coupled2d_boundary_energy(m, s, positions_.data());
    energy_ = {dem_.kinetic + plate_.kinetic, dem_.elastic + plate_.elastic + boundary_,
               dem_.potential + plate_.potential};
    energy_step_ = s.step;
  }
  return energy_;
}

EnergyTotals Coupled2dRun::totals() const {
  energy();
  const double plate = plate_algorithmic_energy(world_.model.plate, world_.state.plate);
  const double in_motion = dem_.kinetic + dem_.elastic + boundary_ + plate;
  return {in_motion + dem_.potential, in_motion, in_motion + std::fabs(dem_.potential)};
}

}  // namespace xfdem::scene
