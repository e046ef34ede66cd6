#include "scene/coupled2d_run.hpp"

#include <cmath>

namespace xfdem::scene {

Coupled2dRun::Coupled2dRun(const Scene& scene, ParallelFor parallel) {
  const BuildResult built = world_.build(coupled2d_desc(scene));
  if (!built.ok()) throw build_refusal(scene, Built::coupled, built);
  world_.workspace.dem.parallel = parallel;
  positions_.assign(2 * world_.model.boundary.vertices.size(), 0.0);
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

}  // namespace xfdem::scene
