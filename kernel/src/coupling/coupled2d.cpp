// The coupled 2D stepper: disks against the plate's boundary
// (include/xfdem/coupled2d.hpp).
#include "xfdem/coupled2d.hpp"

#include <algorithm>
#include <cmath>

#include "dem/contact_law.hpp"
#include "dem/granular.hpp"
#include "xfdem/coupled.hpp"

namespace xfdem {

namespace {

using Code = BuildResult::Code;

/// The boundary at fraction s of the window: vertices lerped from start to end.
void boundary_at(const Coupled2dWorkspace& w, double s, double* positions) {
  const std::size_t n = w.start_positions.size();
  for (std::size_t k = 0; k < n; ++k)
    positions[k] = w.start_positions[k] + s * (w.end_positions[k] - w.start_positions[k]);
}

/// The velocity of a contact's point over the window: its vertices' (Δx/dt), lerped along the segment.
void contact_velocity(const PlateBoundary& b, const Coupled2dWorkspace& w, const PlateBoundaryContact& c, double dt,
                      double out[2]) {
  auto vertex_velocity = [&](int v, int axis) {
    const auto k = static_cast<std::size_t>(2 * v + axis);
    return (w.end_positions[k] - w.start_positions[k]) / dt;
  };
  auto edge_velocity = [&](int segment, double t, int axis) {
    const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(segment)];
    return (1.0 - t) * vertex_velocity(s.a, axis) + t * vertex_velocity(s.b, axis);
  };
  for (int axis = 0; axis < 2; ++axis) {
    if (c.vertex >= 0) {
      out[axis] = vertex_velocity(c.vertex, axis);
    } else if (c.partner >= 0) {  // a blended contact: its point moves as the blend of the two feet
      out[axis] = (1.0 - c.partner_weight) * edge_velocity(c.segment, c.t, axis) +
                  c.partner_weight * edge_velocity(c.partner, c.partner_t, axis);
    } else {
      out[axis] = edge_velocity(c.segment, c.t, axis);
    }
  }
}

/// Normal force (compressive positive) of disk i against a contact with the
/// boundary moving at `speed`: the plane contact's law (K = k_i, η = 2ζ√(k_i m_i)).
double contact_force(const DemModel<2>& dem, std::int32_t i, const PlateBoundaryContact& c, const double v[2],
                     const double speed[2]) {
  const double rate = (speed[0] - v[0]) * c.normal[0] + (speed[1] - v[1]) * c.normal[1];
  return dem_detail::normal_force(dem.law == ContactLaw::linear_nontensile, dem.stiffness[static_cast<std::size_t>(i)],
                                  dem.damping_ratio > 0 ? dem.plane_eta[static_cast<std::size_t>(i)] : 0.0, c.overlap,
                                  rate);
}

using Share = Coupled2dWorkspace::PlateShare;

/// The contacts of disk i (centre, velocity v) with the boundary at
/// `positions` (moving at the window's velocity): adds their force on the
/// disk to total[2] and lists at `shares` (advanced past them) each
/// contact's −scale·F at its material point and scale·F·V (V the contact
/// point's velocity), for spread_shares. Returns the number of contacts that
/// carried a force. The frictionless disk–boundary contact (the plane's
/// normal law), for the held substeps and the hooked stages alike; rotating
/// disks take the wall contact in rotating_contacts.
int boundary_contact_forces(const Coupled2dModel& m, const Coupled2dWorkspace& w, const double* positions,
                            std::int32_t i, const double centre[2], const double v[2], double scale, double total[2],
                            Share*& shares) {
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  const int count = plate_boundary_contacts(m.boundary, positions, centre, m.dem.radius[static_cast<std::size_t>(i)],
                                            contacts);
  int carried = 0;
  for (int c = 0; c < count; ++c) {
    double speed[2];
    contact_velocity(m.boundary, w, contacts[c], m.dt, speed);
    const double fn = contact_force(m.dem, i, contacts[c], v, speed);
    if (fn == 0.0) continue;
    ++carried;
    const double on_disk[2] = {fn * contacts[c].normal[0], fn * contacts[c].normal[1]};
    total[0] += on_disk[0], total[1] += on_disk[1];
    // The plate gets the opposite, at the contact's material point.
    Share& share = *shares++;
    share.points = plate_boundary_material_points(m.boundary, contacts[c], share.at, share.at_share);
    share.force[0] = -scale * on_disk[0], share.force[1] = -scale * on_disk[1];
    share.work = scale * (on_disk[0] * speed[0] + on_disk[1] * speed[1]);
    share.couple_segment = share.couple_partner = -1;
  }
  return carried;
}

/// Adds a couple C (N·m·s here: an impulse's moment) to the plate as two
/// opposite forces at the segment's ends, ±C (ẑ × L)/|L|² with L its
/// reference direction: no net force, moment C for every rigid motion.
void spread_couple(const PlateModel& plate, const PlateBoundary& b, int segment, double couple, double* f) {
  const PlateBoundarySegment& seg = b.segments[static_cast<std::size_t>(segment)];
  const PlateBoundaryVertex& va = b.vertices[static_cast<std::size_t>(seg.a)];
  const PlateBoundaryVertex& vb = b.vertices[static_cast<std::size_t>(seg.b)];
  const double l[2] = {vb.x[0] - va.x[0], vb.x[1] - va.x[1]};
  const double scale = couple / (l[0] * l[0] + l[1] * l[1]);
  const double at_b[2] = {-scale * l[1], scale * l[0]}, at_a[2] = {-at_b[0], -at_b[1]};
  plate_spread_force(plate, vb.at, at_b, f);
  plate_spread_force(plate, va.at, at_a, f);
}

constexpr int kShareSlots = kPlateBoundaryMaxContacts;  // per disk: as many as its contacts

/// Runs f(part, begin, end, shares) over the DEM's parts of the disks
/// (through the DEM's ParallelFor), shares the part's own list, and counts
/// what each part listed.
template <class F>
void over_disk_parts(const Coupled2dModel& m, Coupled2dWorkspace& w, F&& f) {
  const int parts = m.dem.parts > 1 ? 2 : 1;
  for_parts(w.dem.parallel, parts, [&](int part) {
    const std::int32_t begin = part == 0 ? 0 : m.dem.split, end = parts == 2 && part == 0 ? m.dem.split : m.dem.n;
    Share* const first = w.shares.data() + static_cast<std::size_t>(begin) * kShareSlots;
    Share* shares = first;
    f(part, begin, end, shares);
    w.share_count[part] = static_cast<std::int32_t>(shares - first);
  });
  if (parts == 1) w.share_count[1] = 0;
}

/// The parts' lists onto the plate's unknowns `plate` and the book `work`,
/// part 0's then part 1's: disk order, whatever ran them.
void spread_shares(const Coupled2dModel& m, const Coupled2dWorkspace& w, double* plate, double& work) {
  for (int part = 0; part < 2; ++part) {
    const std::int32_t begin = part == 0 ? 0 : m.dem.split;
    const Share* share = w.shares.data() + static_cast<std::size_t>(begin) * kShareSlots;
    for (std::int32_t k = 0; k < w.share_count[part]; ++k, ++share) {
      work -= share->work;
      if (share->points == 1) {
        plate_spread_force(m.plate, share->at[0], share->force, plate);
      } else {  // shared by its points (a blended contact's two feet, a segment's two ends)
        for (int q = 0; q < share->points; ++q) {
          const double piece[2] = {share->at_share[q] * share->force[0], share->at_share[q] * share->force[1]};
          plate_spread_force(m.plate, share->at[q], piece, plate);
        }
      }
      if (share->couple_segment < 0) continue;
      work += share->couple_work;
      if (share->couple_partner < 0) {
        spread_couple(m.plate, m.boundary, share->couple_segment, share->couple, plate);
      } else {  // a blended contact's couple, shared by its two edges as its force is
        spread_couple(m.plate, m.boundary, share->couple_segment, (1.0 - share->partner_weight) * share->couple,
                      plate);
        spread_couple(m.plate, m.boundary, share->couple_partner, share->partner_weight * share->couple, plate);
      }
    }
  }
}

/// The totals the DEM weighs for the hooked integrators (DemDesc::
/// external_contact_totals), after its planes: the plate's force per unknown,
/// then these.
enum HookTotal : int { kForceX, kForceY, kWork, kContacts, kHookExtras };

bool hooked(const Coupled2dModel& m) { return m.dem.features.external_contacts; }

/// Where the hook's totals start in the DEM's plane ledger.
std::size_t ledger_start(const Coupled2dModel& m) { return m.dem.plane_point.size(); }

/// The DEM's external contact hook: the disks against the boundary where it
/// is at the stage's time (lerped over the window), their force added to the
/// accelerations, the plate's share (−F spread to its unknowns), their total
/// force, −F·V and the number of contacts left in `totals` for the
/// integrator's weights.
std::uint64_t boundary_stage(void* context, double time, ConstColumns<2> x, ConstColumns<2> v, Columns<2> a,
                             double* totals) {
  Coupled2dWorkspace& w = *static_cast<Coupled2dWorkspace*>(context);
  const Coupled2dModel& m = *w.stage_model;
  Coupled2dState& s = *w.stage_state;
  const auto dofs = static_cast<std::size_t>(m.plate.dofs);
  std::fill(totals, totals + dofs + kHookExtras, 0.0);
  boundary_at(w, (time - w.dem_start.time) / m.dt, w.positions.data());
  double* extra = totals + dofs;
  std::uint64_t tags[2] = {0, 0};  // sums of integers: the same total in any order
  over_disk_parts(m, w, [&](int part, std::int32_t begin, std::int32_t end, Share*& shares) {
    for (std::int32_t i = begin; i < end; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      const double centre[2] = {x[0][iu], x[1][iu]};
      const double velocity[2] = {v[0][iu], v[1][iu]};
      double total[2] = {0, 0};
      const int carried = boundary_contact_forces(m, w, w.positions.data(), i, centre, velocity, 1.0, total, shares);
      s.boundary_force[0][iu] = total[0];
      s.boundary_force[1][iu] = total[1];
      w.carried[iu] = carried;
      if (carried == 0) continue;
      a[0][iu] += total[0] * m.dem.inv_mass[iu];
      a[1][iu] += total[1] * m.dem.inv_mass[iu];
      tags[part] += (static_cast<std::uint64_t>(i) + 1) * 0xD6E8FEB86659FD93ull;
    }
  });
  // The totals in disk order, on the calling thread.
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    if (w.carried[iu] == 0) continue;
    extra[kForceX] += s.boundary_force[0][iu];
    extra[kForceY] += s.boundary_force[1][iu];
    extra[kContacts] += w.carried[iu];
  }
  spread_shares(m, w, totals, extra[kWork]);
  return tags[0] + tags[1];
}

double norm(const std::vector<double>& x) {
  double s = 0;
  for (const double v : x) s += v * v;
  return std::sqrt(s);
}

/// Σ of the unknowns' shares as a rigid translation along `axis` sees them.
double translation_share(const PlateModel& m, const std::vector<double>& f, int axis) {
  double sum = 0;
  for (int n = 0; n < m.nodes; ++n) {
    const int dof = m.node_dof[static_cast<std::size_t>(2 * n + axis)];
    if (dof >= 0) sum += f[static_cast<std::size_t>(dof)];
  }
  return sum;
}

/// The rate at which a segment turns over the window (rad/s): its ends'
/// relative displacement across its reference direction L, L × (Δb − Δa) / |L|²
/// / dt, the rotation on which spread_couple's couple does its work on the plate.
double segment_spin(const PlateBoundary& b, const Coupled2dWorkspace& w, int segment, double dt) {
  const PlateBoundarySegment& seg = b.segments[static_cast<std::size_t>(segment)];
  const PlateBoundaryVertex& va = b.vertices[static_cast<std::size_t>(seg.a)];
  const PlateBoundaryVertex& vb = b.vertices[static_cast<std::size_t>(seg.b)];
  const double l[2] = {vb.x[0] - va.x[0], vb.x[1] - va.x[1]};
  double d[2];
  for (int axis = 0; axis < 2; ++axis) {
    const auto ka = static_cast<std::size_t>(2 * seg.a + axis), kb = static_cast<std::size_t>(2 * seg.b + axis);
    d[axis] = (w.end_positions[kb] - w.start_positions[kb]) - (w.end_positions[ka] - w.start_positions[ka]);
  }
  return (l[0] * d[1] - l[1] * d[0]) / (l[0] * l[0] + l[1] * l[1]) / dt;
}

/// A segment's quantity at a contact: its segment's, or a blended contact's
/// blend (1 − w)·its edge's + w·the partner's, as its force is shared.
template <class F>
double over_segments(const PlateBoundaryContact& ct, F&& of_segment) {
  if (ct.partner < 0) return of_segment(ct.segment);
  return (1.0 - ct.partner_weight) * of_segment(ct.segment) + ct.partner_weight * of_segment(ct.partner);
}

/// The hertz compliances (1 − ν²)/E and 2(2 − ν)(1 + ν)/E of the material
/// the boundary's segment bounds (the plate's, or an inclusion's where the
/// segment lies in it); 0 for the other laws.
void segment_compliance(const Coupled2dModel& m, int segment, double& inv_e, double& inv_g) {
  if (m.segment_inv_e.empty()) {
    inv_e = m.plate_inv_e, inv_g = m.plate_inv_g;
    return;
  }
  inv_e = m.segment_inv_e[static_cast<std::size_t>(segment)];
  inv_g = m.segment_inv_g[static_cast<std::size_t>(segment)];
}

/// The rotating disk i (centre, velocity v, spin wi) against the boundary at
/// `positions` moving at the window's velocities: each contact the DEM's
/// particle–wall contact, its spring (from s.springs, matched by chain and
/// normal) advanced by `advance`, the springs kept in s.springs when `keep`
/// (false: a stage that only reads them). Adds the boundary's force on the
/// disk to total[2] and its torque to `torque`; lists at `shares` (advanced
/// past them) each contact's plate share −scale·F at its material point, its
/// scale·F·V, and its rolling couple and the couple's work, for
/// spread_shares. Returns the number of contacts that carried a normal force.
int rotating_contacts(const Coupled2dModel& m, Coupled2dState& s, const Coupled2dWorkspace& w, std::int32_t i,
                      const double* positions, const double centre[2], const double (&v)[2], double wi, double advance,
                      bool keep, double scale, Share*& shares, double total[2], double& torque) {
  const auto iu = static_cast<std::size_t>(i);
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  const int count = plate_boundary_contacts(m.boundary, positions, centre, m.dem.radius[iu], contacts);
  // The disk's springs: a contact takes the stored one of its chain whose
  // normal is nearest its own (within 60°, the contact finder's separation).
  constexpr int K = kPlateBoundaryMaxContacts;
  const std::size_t base = iu * K;
  bool taken[K] = {};
  std::int32_t chains[K];
  double normals[K][2], springs[K][2];
  int carried = 0;
  for (int c = 0; c < count; ++c) {
    const PlateBoundaryContact& ct = contacts[c];
    const int chain = m.boundary.segments[static_cast<std::size_t>(ct.segment)].chain;
    int found = -1;
    double nearest = 0.5;
    for (int k = 0; k < K; ++k) {
      const std::size_t slot = base + static_cast<std::size_t>(k);
      if (taken[k] || s.springs.chain[slot] != chain) continue;
      const double cosine = s.springs.normal[2 * slot] * ct.normal[0] + s.springs.normal[2 * slot + 1] * ct.normal[1];
      if (cosine > nearest) nearest = cosine, found = k;
    }
    double xi[2] = {0.0, 0.0};
    if (found >= 0) {
      taken[found] = true;
      const std::size_t slot = base + static_cast<std::size_t>(found);
      xi[0] = s.springs.xi[2 * slot], xi[1] = s.springs.xi[2 * slot + 1];
    }
    dem_detail::WallContact<2> wall{};
    contact_velocity(m.boundary, w, ct, m.dt, wall.velocity);
    wall.normal[0] = ct.normal[0], wall.normal[1] = ct.normal[1];
    wall.speed = wall.velocity[0] * ct.normal[0] + wall.velocity[1] * ct.normal[1];
    // The boundary's spin there; a blended contact's is the blend of its two
    // edges' (at a node that the plate bends, the two turn apart, and the
    // nearer edge's alone would jump as the contact moves across).
    const double spin = over_segments(ct, [&](int k) { return segment_spin(m.boundary, w, k, m.dt); });
    wall.spin = &spin;
    segment_compliance(m, ct.segment, wall.inv_e, wall.inv_g);
    // Rolling resistance holds the disk within the substep h at every
    // evaluation, its contact's tangential torque included: a disk resting on
    // the plate's bent top (a tilted normal) needs a couple against that torque,
    // which the plane's clamp gives only while the disk rolls, at h τ_t / I
    // (it crept); and the stepper's re-evaluation at a window's start (h = 0)
    // would otherwise take the uncapped torque ±μ_r r F_n, whose sign flips
    // with the pass's boundary spin (windows left at a jump).
    wall.hold = m.dem.dt;
    // The boundary turns back under the couple: over a light plate's segment
    // the disk's I/h alone would make the window's map far too steep in the
    // boundary's spin (the passes could not settle).
    if (!m.segment_inv_turn.empty())
      wall.inv_inertia = over_segments(ct, [&](int k) { return m.segment_inv_turn[static_cast<std::size_t>(k)]; });
    // The arm to the contact point on the boundary, p − x = −(r − δ) n: the
    // disk's torque is (p − x) × F, the plate's moment of −F at p its exact
    // opposite, and the sliding velocity is that of the disk's point at p.
    wall.arm = ct.partner < 0 ? m.dem.radius[iu] - ct.overlap
                              : std::hypot(centre[0] - ct.point[0], centre[1] - ct.point[1]);
    const dem_detail::ContactResult<2> r = dem_detail::wall_contact<2>(m.dem, i, wall, ct.overlap, v, &wi, advance, xi);
    chains[c] = chain;
    normals[c][0] = ct.normal[0], normals[c][1] = ct.normal[1];
    springs[c][0] = xi[0], springs[c][1] = xi[1];
    carried += r.fn != 0.0 ? 1 : 0;
    const double on_disk[2] = {r.fn * r.normal[0] + r.ft[0], r.fn * r.normal[1] + r.ft[1]};
    total[0] += on_disk[0], total[1] += on_disk[1];
    torque += r.torque_j[0];
    Share& share = *shares++;
    share.points = plate_boundary_material_points(m.boundary, ct, share.at, share.at_share);
    share.partner_weight = ct.partner_weight;
    share.force[0] = -scale * on_disk[0], share.force[1] = -scale * on_disk[1];
    share.work = scale * (on_disk[0] * wall.velocity[0] + on_disk[1] * wall.velocity[1]);
    share.couple_segment = share.couple_partner = -1;
    if (r.torque_i[0] != 0.0) {
      share.couple_segment = ct.segment;
      share.couple_partner = ct.partner;
      share.couple = scale * r.torque_i[0];
      share.couple_work = scale * r.torque_i[0] * spin;
    }
  }
  if (!keep) return carried;
  for (int k = 0; k < K; ++k) {
    const std::size_t slot = base + static_cast<std::size_t>(k);
    const bool used = k < count;
    s.springs.chain[slot] = used ? chains[k] : -1;
    s.springs.normal[2 * slot] = used ? normals[k][0] : 0.0;
    s.springs.normal[2 * slot + 1] = used ? normals[k][1] : 0.0;
    s.springs.xi[2 * slot] = used ? springs[k][0] : 0.0;
    s.springs.xi[2 * slot + 1] = used ? springs[k][1] : 0.0;
  }
  return carried;
}

/// The boundary's force (x, y; N) and torque (N·m) on disk i at the disks'
/// state in s.dem, the boundary at `positions` (2 per vertex) moving at the
/// window's velocities, held over a substep h (symplectic Euler): each
/// contact's plate share of h·F (and of its rolling couple) and the disk's
/// work on the boundary over h are listed at `shares`. Rotating disks: each
/// contact's spring advanced by h and kept (rotating_contacts).
void disk_contacts(const Coupled2dModel& m, Coupled2dState& s, const Coupled2dWorkspace& w, std::int32_t i,
                   const double* positions, double h, double total[2], double& torque, Share*& shares) {
  const auto iu = static_cast<std::size_t>(i);
  const double centre[2] = {s.dem.x[0][iu], s.dem.x[1][iu]};
  const double v[2] = {s.dem.v[0][iu], s.dem.v[1][iu]};
  total[0] = total[1] = 0.0;
  torque = 0.0;
  if (!m.rotating) {
    boundary_contact_forces(m, w, positions, i, centre, v, h, total, shares);
    return;
  }
  rotating_contacts(m, s, w, i, positions, centre, v, s.dem.w[0][iu], h, true, h, shares, total, torque);
}

/// The rotating DEM's external contact hook (DemDesc::external_contacts, the
/// granular step): boundary_stage's evaluation with friction, rolling
/// resistance or hertz, the springs advanced by the stage's `advance` from
/// those kept at the substep's start and kept at its last evaluation, as the
/// DEM treats its planes' springs; the torques added to the angular
/// accelerations.
std::uint64_t boundary_rotating_stage(void* context, const ExternalStage<2>& at, double* totals) {
  Coupled2dWorkspace& w = *static_cast<Coupled2dWorkspace*>(context);
  const Coupled2dModel& m = *w.stage_model;
  Coupled2dState& s = *w.stage_state;
  const auto dofs = static_cast<std::size_t>(m.plate.dofs);
  std::fill(totals, totals + dofs + kHookExtras, 0.0);
  boundary_at(w, (at.time - w.dem_start.time) / m.dt, w.positions.data());
  double* extra = totals + dofs;
  std::uint64_t tags[2] = {0, 0};
  over_disk_parts(m, w, [&](int part, std::int32_t begin, std::int32_t end, Share*& shares) {
    for (std::int32_t i = begin; i < end; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      const double centre[2] = {at.x[0][iu], at.x[1][iu]};
      const double velocity[2] = {at.v[0][iu], at.v[1][iu]};
      double total[2] = {0, 0}, torque = 0;
      const int carried = rotating_contacts(m, s, w, i, w.positions.data(), centre, velocity, at.spin[0][iu],
                                            at.advance, at.keep, 1.0, shares, total, torque);
      s.boundary_force[0][iu] = total[0];
      s.boundary_force[1][iu] = total[1];
      w.carried[iu] = carried;
      at.a[0][iu] += total[0] * m.dem.inv_mass[iu];
      at.a[1][iu] += total[1] * m.dem.inv_mass[iu];
      at.alpha[0][iu] += torque * m.dem.inv_inertia[iu];
      tags[part] += carried > 0 ? (static_cast<std::uint64_t>(i) + 1) * 0xD6E8FEB86659FD93ull : 0;
    }
  });
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    extra[kForceX] += s.boundary_force[0][iu];
    extra[kForceY] += s.boundary_force[1][iu];
    extra[kContacts] += w.carried[iu];
  }
  spread_shares(m, w, totals, extra[kWork]);
  return tags[0] + tags[1];
}

/// One pass over the window with the plate's force `force`: the plate
/// stepped from its start, the disks substepped against the boundary moving
/// between the plate's two places; the impulse the plate should receive is
/// left in w.impulse. Returns the halves' flags.
StepStatus window_pass(const Coupled2dModel& m, Coupled2dState& s, Coupled2dWorkspace& w, double impulse_taken[2],
                       double& work) {
  StepStatus status = StepStatus::ok;
  s.plate = w.plate_start;
  dem_copy_state(s.dem, w.dem_start);
  if (m.rotating) s.springs = w.springs_start;
  status |= plate_start_acceleration(m.plate, s.plate, w.plate);
  status |= without(plate_step(m.plate, s.plate, w.plate), StepStatus::energy_growth);
  plate_boundary_positions(m.plate, m.boundary, s.plate.u.data(), s.plate.time, w.end_positions.data());
  if (!plate_boundary_within_reach(m.boundary, w.end_positions.data())) status |= StepStatus::coupling_unstable;
  std::fill(w.impulse.begin(), w.impulse.end(), 0.0);
  impulse_taken[0] = impulse_taken[1] = 0.0;
  work = 0.0;
  const double h = m.dem.dt;
  const int n = m.substeps;
  if (hooked(m)) {
    // The DEM evaluates the boundary at its stages (boundary_stage) and
    // weighs the plate's share as it weighs the forces.
    const std::size_t start = ledger_start(m), dofs = w.impulse.size();
    for (std::size_t k = start; k < s.dem.plane_impulse.size(); ++k) s.dem.plane_impulse[k] = 0.0;
    for (int k = 0; k < n; ++k) status |= without(dem_step(m.dem, s.dem, w.dem), StepStatus::energy_growth);
    const double* ledger = s.dem.plane_impulse.data() + start;
    for (std::size_t k = 0; k < dofs; ++k) w.impulse[k] = ledger[k];
    impulse_taken[0] = ledger[dofs + kForceX];
    impulse_taken[1] = ledger[dofs + kForceY];
    work = ledger[dofs + kWork];
    return status;
  }
  for (int k = 0; k < n; ++k) {
    boundary_at(w, static_cast<double>(k) / n, w.positions.data());
    over_disk_parts(m, w, [&](int, std::int32_t begin, std::int32_t end, Share*& shares) {
      for (std::int32_t i = begin; i < end; ++i) {
        const auto iu = static_cast<std::size_t>(i);
        double total[2], torque;
        disk_contacts(m, s, w, i, w.positions.data(), h, total, torque, shares);
        s.dem.external_force[0][iu] = total[0];
        s.dem.external_force[1][iu] = total[1];
        if (m.rotating) s.dem.external_torque[0][iu] = torque;
      }
    });
    // The sums in disk order, on the calling thread.
    for (std::int32_t i = 0; i < m.dem.n; ++i) {
      impulse_taken[0] += h * s.dem.external_force[0][static_cast<std::size_t>(i)];
      impulse_taken[1] += h * s.dem.external_force[1][static_cast<std::size_t>(i)];
    }
    spread_shares(m, w, w.impulse.data(), work);
    dem_inputs_changed(s.dem);
    status |= without(dem_step(m.dem, s.dem, w.dem), StepStatus::energy_growth);
  }
  return status;
}


double dot(const double* a, const double* b, std::size_t n) {
  double s = 0;
  for (std::size_t k = 0; k < n; ++k) s += a[k] * b[k];
  return s;
}

/// The next force of the window, IQN-ILS: the coefficients c that fit the
/// residual's changes V of the last passes to −g (least squares, by a QR of
/// V, newest column first, a column dropped where it adds less than 1e-8 of
/// its length to those before it), then f = −J/dt + W c, W the output's
/// changes. With no columns, Picard's f = −J/dt. `force` enters as the last
/// pass's, w.residual and w.previous_output hold its g and −J/dt.
void quasi_newton_step(Coupled2dWorkspace& w, int columns, int newest, std::vector<double>& force) {
  const std::size_t n = force.size();
  constexpr auto H = static_cast<std::size_t>(kCoupled2dHistory);
  int kept = 0, slot_of[kCoupled2dHistory];
  for (int j = 0; j < columns; ++j) {
    const int slot = (newest - j + kCoupled2dHistory) % kCoupled2dHistory;
    const double* v = w.history_residual.data() + static_cast<std::size_t>(slot) * n;
    double* qk = w.q.data() + static_cast<std::size_t>(kept) * n;
    for (std::size_t k = 0; k < n; ++k) qk[k] = v[k];
    const double length = std::sqrt(dot(v, v, n));
    for (int i = 0; i < kept; ++i) {  // modified Gram–Schmidt
      const double* qi = w.q.data() + static_cast<std::size_t>(i) * n;
      const double rik = dot(qi, qk, n);
      for (std::size_t k = 0; k < n; ++k) qk[k] -= rik * qi[k];
      w.r[static_cast<std::size_t>(i) * H + static_cast<std::size_t>(kept)] = rik;
    }
    const double rkk = std::sqrt(dot(qk, qk, n));
    if (!(rkk > 1e-8 * length)) continue;
    for (std::size_t k = 0; k < n; ++k) qk[k] /= rkk;
    w.r[static_cast<std::size_t>(kept) * H + static_cast<std::size_t>(kept)] = rkk;
    slot_of[kept++] = slot;
  }
  // R c = −Qᵀ g, by back substitution.
  for (int i = kept - 1; i >= 0; --i) {
    double b = -dot(w.q.data() + static_cast<std::size_t>(i) * n, w.residual.data(), n);
    for (int j = i + 1; j < kept; ++j)
      b -= w.r[static_cast<std::size_t>(i) * H + static_cast<std::size_t>(j)] * w.coefficients[static_cast<std::size_t>(j)];
    w.coefficients[static_cast<std::size_t>(i)] = b / w.r[static_cast<std::size_t>(i) * H + static_cast<std::size_t>(i)];
  }
  for (std::size_t k = 0; k < n; ++k) force[k] = w.previous_output[k];
  for (int i = 0; i < kept; ++i) {
    const double c = w.coefficients[static_cast<std::size_t>(i)];
    const double* dh = w.history_output.data() + static_cast<std::size_t>(slot_of[i]) * n;
    for (std::size_t k = 0; k < n; ++k) force[k] += c * dh[k];
  }
}

/// This pass (g in w.residual, the disks in s) against a kept one: the θ
/// that brings the blend (1 − θ) g + θ g_kept nearest 0, whether that blend
/// is within the tolerance (of the blend of their scales), and whether the
/// two passes' forces (the boundary motions their disks saw) are within the
/// tolerance of each other, as a settled pass's is of its own impulse.
struct Straddle {
  double theta = -1;
  bool blend_settles = false, close = false;
  bool across() const { return theta > 0.0 && theta < 1.0; }
};
Straddle straddle(const Coupled2dWorkspace& w, const Coupled2dWorkspace::Pass& p, double scale) {
  const std::size_t n = w.residual.size();
  const std::vector<double>& force = w.plate.external_force;
  double dd = 0, gd = 0, ff = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = p.residual[k] - w.residual[k];
    dd += d * d, gd += w.residual[k] * d;
    ff += (force[k] - p.force[k]) * (force[k] - p.force[k]);
  }
  Straddle out;
  if (!(dd > 0)) return out;
  out.theta = -gd / dd;
  if (!out.across()) return out;
  double blended = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double g = (1.0 - out.theta) * w.residual[k] + out.theta * p.residual[k];
    blended += g * g;
  }
  const double tolerance = kCoupled2dTolerance * std::min(scale, p.scale);
  out.blend_settles = std::sqrt(blended) <= tolerance;
  out.close = std::sqrt(ff) <= tolerance;
  return out;
}

/// Keeps this pass (the disks in s, the rest in w) as `p`.
void keep_pass(const Coupled2dModel& m, const Coupled2dState& s, Coupled2dWorkspace& w, Coupled2dWorkspace::Pass& p,
               double scale, const double taken[2], double work) {
  dem_copy_state(p.dem, s.dem);
  if (m.rotating) p.springs = s.springs;
  p.residual = w.residual;
  p.force = w.plate.external_force;
  p.impulse = w.impulse;
  p.taken[0] = taken[0], p.taken[1] = taken[1];
  p.work = work, p.scale = scale;
}

/// The window's end across a jump of J: this pass and the kept pass `p`
/// blended, (1 − θ)·this + θ·p: the disks' states (and springs), the
/// impulse, the force, the books alike; the plate is stepped again with the
/// blended impulse at the window's end. False, changing nothing, when the
/// two differ in more than values (their pair lists, their contacts' chains).
bool blend_passes(const Coupled2dModel& m, Coupled2dState& s, Coupled2dWorkspace& w,
                  const Coupled2dWorkspace::Pass& p, double theta, double taken[2], double& work) {
  if (m.rotating && p.springs.chain != s.springs.chain) return false;
  if (!dem_blend_state(s.dem, p.dem, theta)) return false;
  if (m.rotating)
    for (std::size_t k = 0; k < s.springs.xi.size(); ++k) {
      s.springs.xi[k] = (1.0 - theta) * s.springs.xi[k] + theta * p.springs.xi[k];
      s.springs.normal[k] = (1.0 - theta) * s.springs.normal[k] + theta * p.springs.normal[k];
    }
  std::vector<double>& force = w.plate.external_force;
  for (std::size_t k = 0; k < force.size(); ++k) {
    w.impulse[k] = (1.0 - theta) * w.impulse[k] + theta * p.impulse[k];
    force[k] = (1.0 - theta) * force[k] + theta * p.force[k];
  }
  for (int axis = 0; axis < 2; ++axis) taken[axis] = (1.0 - theta) * taken[axis] + theta * p.taken[axis];
  work = (1.0 - theta) * work + theta * p.work;
  return true;
}

}  // namespace

BuildResult build_coupled2d(const Coupled2dDesc& desc, Coupled2dModel& m, Coupled2dState& s, Coupled2dWorkspace& w) {
  m = Coupled2dModel{};
  s = Coupled2dState{};
  w = Coupled2dWorkspace{};
  if (BuildResult r = validate_energy_check(desc.energy_check); !r.ok()) return r;
  if (desc.dem_substeps < 1 || desc.dem_substeps > 1'000'000)
    return BuildResult::failure(Code::invalid_argument, "dem_substeps: must be in [1, 1e6] (got %d)", desc.dem_substeps);
  if (desc.plate.analysis != PlateDesc::Analysis::dynamic)
    return BuildResult::failure(Code::invalid_argument, "continuum.analysis: a coupled scene needs %s", "dynamic");
  const bool rotating = desc.dem.friction > 0 || desc.dem.rolling_friction > 0 || desc.dem.law == ContactLaw::hertz;
  if (desc.dem.integrator == DemIntegrator::abm4_events)
    return BuildResult::failure(Code::invalid_argument,
                                "dem.integrator: %s is not supported against the plate: its event location (frozen "
                                "contact sets, bisection on their changes) does not see the boundary's contacts; use "
                                "abm4, rk4, verlet or symplectic_euler",
                                integrator_name(desc.dem.integrator));
  if (!(std::isfinite(desc.boundary_allowance) && desc.boundary_allowance >= 0))
    return BuildResult::failure(Code::invalid_argument, "boundary_allowance: %g is not a length >= 0",
                                desc.boundary_allowance);
  PlateDesc plate = desc.plate;
  plate.energy_check = kEnergyCheckOff;  // an open system here: the exchange sets its input
  BuildResult r = build_plate(plate, m.plate, s.plate, w.plate);
  if (!r.ok()) return BuildResult::failure(r.code, "continuum.%s", r.message);
  // A disk whose centre is in the plate's material would be thrown out by its contact.
  for (std::size_t i = 0; i < desc.dem.particles.size(); ++i) {
    const auto& p = desc.dem.particles[i];
    if (plate_point_region(plate, p.position[0], p.position[1], 0.0) == 0 ||
        plate_point_region(plate, p.position[0], p.position[1], 0.0) == 1)
      return BuildResult::failure(Code::invalid_argument,
                                  "dem.particles[%zu].position: its centre (%g, %g) is inside the plate's material",
                                  i, p.position[0], p.position[1]);
  }
  DemDesc<2> dem = desc.dem;
  dem.dt = plate.dt / desc.dem_substeps;
  // Symplectic Euler evaluates its forces once, at the substep's start: the
  // boundary's force held over the substep is its own evaluation. The others
  // evaluate at their stages: the boundary is evaluated there (boundary_stage,
  // boundary_rotating_stage with rotation).
  const bool held = desc.dem.integrator == DemIntegrator::symplectic_euler;
  dem.external_forces = held;
  dem.external_torques = rotating && held;
  dem.external_contacts = !held;
  dem.external_contact_totals = held ? 0 : m.plate.dofs + kHookExtras;
  dem.energy_check = kEnergyCheckOff;
  r = build_dem(dem, m.dem, s.dem, w.dem);
  if (!r.ok()) return BuildResult::failure(r.code, "dem.%s", r.message);
  m.substeps = desc.dem_substeps;
  m.dt = plate.dt;
  m.rotating = rotating;
  const bool hertz = desc.dem.law == ContactLaw::hertz;
  // hertz: the stiffest material the disks can touch bounds the stable step.
  double stiffest_inv_e = 0, stiffest_inv_g = 0;
  if (hertz) {
    const double e = plate.youngs_modulus, nu = plate.poisson_ratio;
    m.plate_inv_e = (1.0 - nu * nu) / e;
    m.plate_inv_g = 2.0 * (2.0 - nu) * (1.0 + nu) / e;
    stiffest_inv_e = m.plate_inv_e, stiffest_inv_g = m.plate_inv_g;
    for (const PlateDiscontinuity& q : plate.discontinuities) {
      if (q.kind != PlateDiscontinuity::Kind::inclusion) continue;
      const double ek = q.material.youngs_modulus, nuk = q.material.poisson_ratio;
      stiffest_inv_e = std::min(stiffest_inv_e, (1.0 - nuk * nuk) / ek);
      stiffest_inv_g = std::min(stiffest_inv_g, 2.0 * (2.0 - nuk) * (1.0 + nuk) / ek);
    }
  }

  const double allowance = desc.boundary_allowance > 0
                               ? desc.boundary_allowance
                               : 0.5 * std::min(m.plate.cell_size[0], m.plate.cell_size[1]);
  double max_radius = 0;
  for (const double radius : m.dem.radius) max_radius = std::max(max_radius, radius);
  r = plate_boundary_build(m.plate, max_radius > 0 ? max_radius : 1e-3 * allowance, allowance, m.boundary);
  if (!r.ok()) return r;
  // The lightest mass a contact sees: at a boundary point x the plate's
  // lumped compliance Σ_a N_a(x)² / m_a over the standard functions there
  // (m_a = ρ t ∫ N_a dA over the material, held components included). A
  // contact's force acts at a vertex or, on a plain cell's edge, at a point
  // of it, shared by points with weights summing to 1: by convexity its
  // compliance is at most the largest over the vertices. At a node of an
  // uncut edge it is that node's 1/m_node; a sliver that a void cuts off a
  // cell has a nearly massless node, but its function is as small on the
  // boundary (N² / m stays of the order 1/(ρ t h²)), so it does not set the
  // step (docs/coupled2d.md, "The coupled step").
  double softest = 0;  // 1/m_eff, 1/kg
  PlateMaterialPoint softest_at;
  double softest_x[2] = {0, 0};
  // The lightest node whose function reaches the boundary (a sliver's).
  const double cell_mass = plate.density * plate.thickness * m.plate.cell_size[0] * m.plate.cell_size[1];
  double sliver_mass = INFINITY;
  int sliver_node[2] = {0, 0};
  const PlateBoundaryVertex* sliver_vertex = nullptr;
  for (const PlateBoundaryVertex& v : m.boundary.vertices) {
    PlatePointBasis basis;
    if (!plate_point_basis(m.plate, v.at.cell[0], v.at.cell[1], v.at.xi, v.at.eta, v.at.side, basis, 0.0)) continue;
    double sum = 0;
    for (int q = 0; q < basis.count && q < 4; ++q) {  // the standard functions, counter-clockwise from (i, j)
      const int i = v.at.cell[0] + (q == 1 || q == 2 ? 1 : 0), j = v.at.cell[1] + (q >= 2 ? 1 : 0);
      const double mass = m.plate.node_mass[static_cast<std::size_t>(j * (m.plate.desc.cells[0] + 1) + i)];
      if (mass > 0) sum += basis.n[q] * basis.n[q] / mass;
      if (mass > 0 && basis.n[q] != 0.0 && mass < sliver_mass)
        sliver_mass = mass, sliver_node[0] = i, sliver_node[1] = j, sliver_vertex = &v;
    }
    if (sum > softest) softest = sum, softest_at = v.at, softest_x[0] = v.x[0], softest_x[1] = v.x[1];
  }
  m.coupling_inv_mass = softest;
  // A sliver below kCoupled2dSliverMass of a cell's mass: its stiff, nearly
  // massless mode is excited by the start acceleration the plate re-solves
  // from M at every coupled step, and a disk touching it breaks the step at
  // any substep (docs/coupled2d.md, "The coupled step").
  const bool sliver = sliver_vertex != nullptr && sliver_mass < kCoupled2dSliverMass * cell_mass;
  if (desc.reject_unstable_coupling && sliver) {
    const PlateMaterialPoint& at = sliver_vertex->at;
    const std::size_t cell = static_cast<std::size_t>(at.cell[1] * m.plate.desc.cells[0] + at.cell[0]);
    const int cut = m.plate.cell_cut_by.empty() ? -1 : m.plate.cell_cut_by[cell];
    const double node_x = plate.min[0] + sliver_node[0] * m.plate.cell_size[0];
    const double node_y = plate.min[1] + sliver_node[1] * m.plate.cell_size[1];
    return BuildResult::failure(
        Code::unstable_time_step,
        "continuum.discontinuities.%d: '%s' cuts a sliver off cell (%d, %d) at its boundary point (%g, %g): the "
        "node (%g, %g) keeps %g kg, %.3g of a cell's mass (below %g), and a disk touching the sliver breaks the "
        "coupled step at any substep; move the boundary onto the node's row or column, or further from it",
        cut, cut >= 0 ? plate.discontinuities[static_cast<std::size_t>(cut)].name.c_str() : "the plate", at.cell[0],
        at.cell[1], sliver_vertex->x[0], sliver_vertex->x[1], node_x, node_y, sliver_mass, sliver_mass / cell_mass,
        kCoupled2dSliverMass);
  }

  // The stiffest contact: normal k (hertz: S_n at the DEM's reference overlap
  // kHertzReferenceOverlap · R), and with friction the tangential one, whose
  // disk side also turns (1/m + r²/I).
  double worst = 0;
  bool tangential = false;
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double radius = m.dem.radius[iu];
    double kn = m.dem.stiffness[iu], kt = m.dem.tangential_ratio * kn;
    if (hertz) {
      const double root = radius * std::sqrt(kHertzReferenceOverlap);
      kn = 2.0 * root / (m.dem.hertz_inv_e[iu] + stiffest_inv_e);
      kt = 8.0 * root / (m.dem.hertz_inv_g[iu] + stiffest_inv_g);
    }
    const double normal = kn * (softest + m.dem.inv_mass[iu]);
    if (normal > worst) worst = normal, tangential = false;
    if (desc.dem.friction > 0) {
      const double turning = kt * (softest + m.dem.inv_mass[iu] + radius * radius * m.dem.inv_inertia[iu]);
      if (turning > worst) worst = turning, tangential = true;
    }
  }
  m.coupling_omega = std::sqrt(worst);
  const double factor = m.dem.stable_factor;  // the integrator's, at the law's damping
  m.beyond_stable_step =
      sliver || m.coupling_omega * dem.dt > factor || m.coupling_omega * m.dt > kCoupledMaxOmegaDt;
  const char* mode = tangential ? "tangential (friction): omega = sqrt(k_t (1/m_eff + 1/m + r^2/I))"
                                : "normal: omega = sqrt(k (1/m_eff + 1/m))";
  if (desc.reject_unstable_coupling && m.coupling_omega * dem.dt > factor)
    return BuildResult::failure(Code::unstable_time_step,
                                "dem_substeps: the disk substep %g s (dt / dem_substeps) exceeds the stable step %g s "
                                "of %s for a disk on the plate's softest boundary point (%g, %g) in cell (%d, %d) "
                                "(effective mass m_eff = %g kg; %s = %g rad/s); raise dem_substeps or reduce time.dt",
                                dem.dt, factor / m.coupling_omega, integrator_name(dem.integrator), softest_x[0],
                                softest_x[1], softest_at.cell[0], softest_at.cell[1], softest > 0 ? 1.0 / softest : 0.0,
                                mode, m.coupling_omega);
  if (desc.reject_unstable_coupling && m.coupling_omega * m.dt > kCoupledMaxOmegaDt)
    return BuildResult::failure(Code::unstable_time_step,
                                "time.dt: %g s is too long for the disk-plate exchange to settle: omega*dt = %.3g > "
                                "%.3g at the plate's softest boundary point (%g, %g) in cell (%d, %d) (effective mass "
                                "m_eff = %g kg; %s = %g rad/s); reduce time.dt",
                                m.dt, m.coupling_omega * m.dt, kCoupledMaxOmegaDt, softest_x[0], softest_x[1],
                                softest_at.cell[0], softest_at.cell[1], softest > 0 ? 1.0 / softest : 0.0, mode,
                                m.coupling_omega);
  if (hertz && !plate.discontinuities.empty()) {
    // Each segment's material: that of its cell on its side (an inclusion's
    // on the inclusion's negative side, as the plate integrates it; in a
    // cell cut by a crack and an inclusion, by the inclusion's level set at
    // the segment, which the build splits where it crosses zero).
    m.segment_inv_e.assign(m.boundary.segments.size(), m.plate_inv_e);
    m.segment_inv_g.assign(m.boundary.segments.size(), m.plate_inv_g);
    for (std::size_t k = 0; k < m.boundary.segments.size(); ++k) {
      const int material = plate_boundary_segment_material(m.plate, m.boundary.segments[k]);
      if (material <= 0) continue;
      const PlateMaterial& q = plate.discontinuities[static_cast<std::size_t>(material - 1)].material;
      m.segment_inv_e[k] = (1.0 - q.poisson_ratio * q.poisson_ratio) / q.youngs_modulus;
      m.segment_inv_g[k] = 2.0 * (2.0 - q.poisson_ratio) * (1.0 + q.poisson_ratio) / q.youngs_modulus;
    }
  }

  const auto dofs = static_cast<std::size_t>(m.plate.dofs);
  if (desc.dem.rolling_friction > 0) {
    // Each segment's turning compliance under a couple at its ends: a force
    // across it at each end, spread to the unknowns, over the lumped masses.
    std::vector<double> f(dofs, 0.0);
    auto inv_mass = [&](const PlateMaterialPoint& at, const double across[2]) {
      plate_spread_force(m.plate, at, across, f.data());
      double sum = 0;
      for (int n = 0; n < m.plate.nodes; ++n)
        for (int c = 0; c < 2; ++c) {
          const int dof = m.plate.node_dof[static_cast<std::size_t>(2 * n + c)];
          const double mass = m.plate.node_mass[static_cast<std::size_t>(n)];
          if (dof >= 0 && mass > 0) sum += f[static_cast<std::size_t>(dof)] * f[static_cast<std::size_t>(dof)] / mass;
        }
      std::fill(f.begin(), f.end(), 0.0);
      return sum;
    };
    m.segment_inv_turn.assign(m.boundary.segments.size(), 0.0);
    for (std::size_t k = 0; k < m.boundary.segments.size(); ++k) {
      const PlateBoundarySegment& seg = m.boundary.segments[k];
      const PlateBoundaryVertex& va = m.boundary.vertices[static_cast<std::size_t>(seg.a)];
      const PlateBoundaryVertex& vb = m.boundary.vertices[static_cast<std::size_t>(seg.b)];
      const double l[2] = {vb.x[0] - va.x[0], vb.x[1] - va.x[1]};
      const double length2 = l[0] * l[0] + l[1] * l[1];
      if (!(length2 > 0)) continue;
      const double across[2] = {-l[1] / std::sqrt(length2), l[0] / std::sqrt(length2)};
      m.segment_inv_turn[k] = (inv_mass(va.at, across) + inv_mass(vb.at, across)) / length2;
    }
  }
  const std::size_t coords = 2 * m.boundary.vertices.size();
  w.plate.external_force.assign(dofs, 0.0);
  s.coupling_force.assign(dofs, 0.0);
  w.impulse.assign(dofs, 0.0);
  w.residual.assign(dofs, 0.0);
  w.previous_residual.assign(dofs, 0.0);
  w.best_force.assign(dofs, 0.0);
  constexpr auto history = static_cast<std::size_t>(kCoupled2dHistory);
  w.history_residual.assign(history * dofs, 0.0);
  w.history_output.assign(history * dofs, 0.0);
  w.q.assign(history * dofs, 0.0);
  w.r.assign(history * history, 0.0);
  w.coefficients.assign(history, 0.0);
  w.previous_output.assign(dofs, 0.0);
  if (rotating) {
    const auto slots = static_cast<std::size_t>(m.dem.n) * kPlateBoundaryMaxContacts;
    s.springs.chain.assign(slots, -1);
    s.springs.normal.assign(2 * slots, 0.0);
    s.springs.xi.assign(2 * slots, 0.0);
    w.springs_start = s.springs;
  }
  w.shares.assign(static_cast<std::size_t>(m.dem.n) * kShareSlots, Coupled2dWorkspace::PlateShare{});
  w.carried.assign(static_cast<std::size_t>(m.dem.n), 0);
  w.start_positions.assign(coords, 0.0);
  w.end_positions.assign(coords, 0.0);
  w.positions.assign(coords, 0.0);
  if (!held)
    for (auto& f : s.boundary_force) f.assign(static_cast<std::size_t>(m.dem.n), 0.0);
  w.dem_start = s.dem;
  for (Coupled2dWorkspace::Pass& p : w.kept) {
    p.dem = s.dem;
    p.springs = s.springs;
    p.residual.assign(dofs, 0.0);
    p.force.assign(dofs, 0.0);
    p.impulse.assign(dofs, 0.0);
  }
  w.plate_start = s.plate;
  m.energy_check = desc.energy_check;
  m.built = true;
  coupled2d_restart_energy_ledger(m, s, w);
  return BuildResult::success();
}

StepStatus coupled2d_step(const Coupled2dModel& m, Coupled2dState& s, Coupled2dWorkspace& w) {
  if (!m.built) return StepStatus::not_built;
  // The work the halves book over the step (the energy check's W).
  const double booked_before = s.plate.energy.work + s.dem.energy.work;
  if (hooked(m)) {
    // Installed at every step: the world may have been copied since.
    w.dem.external_contacts = &boundary_stage;
    w.dem.external_rotating_contacts = &boundary_rotating_stage;
    w.dem.external_context = &w;
    w.stage_model = &m;
    w.stage_state = &s;
    // The acceleration kept from the last window saw that window's boundary
    // motion: while a disk touches the boundary, it is evaluated again with
    // this window's, and a multistep history restarts, as the 1D stepper's
    // moving top does (dem_drive_plane). At the first step it was evaluated
    // without the boundary (build_dem).
    const std::size_t touching = ledger_start(m) + static_cast<std::size_t>(m.plate.dofs) + kContacts;
    if (s.step == 0 || s.dem.hist_plane_force[static_cast<std::size_t>(s.dem.history_head)][touching] != 0.0)
      dem_inputs_changed(s.dem);
  }
  dem_copy_state(w.dem_start, s.dem);
  w.plate_start = s.plate;
  if (m.rotating) w.springs_start = s.springs;
  plate_boundary_positions(m.plate, m.boundary, s.plate.u.data(), s.plate.time, w.start_positions.data());
  std::vector<double>& force = w.plate.external_force;
  force = s.coupling_force;  // the first pass: last window's force
  const auto dofs = force.size();
  StepStatus status = StepStatus::ok;
  double taken[2] = {0, 0}, work_by_particles = 0;
  int passes = 0, best_pass = 0, columns = 0, newest = -1;
  double best = INFINITY;  // the smallest |g|/scale seen, at w.best_force
  bool last_is_best = false, bisecting = false, restarted = false;
  while (true) {
    StepStatus pass = window_pass(m, s, w, taken, work_by_particles);
    ++passes;
    // g = −J/dt − f̄ (w.impulse holds the plate's share −J already).
    for (std::size_t k = 0; k < dofs; ++k) w.residual[k] = w.impulse[k] / m.dt - force[k];
    const double scale = norm(force) + norm(w.impulse) / m.dt;
    const double g = scale > 0 ? norm(w.residual) / scale : 0.0;
    last_is_best = g < best;
    if (last_is_best) {
      best = g, best_pass = passes;
      w.best_force = force;
    }
    if (g <= kCoupled2dTolerance || has(pass, StepStatus::non_finite)) {
      status |= pass;
      break;
    }
    // This pass and a kept one on the two sides of a jump of J (a contact
    // closing at another substep or stage: no force is a fixed point there):
    // where the blend (1 − θ) g + θ g_kept of their residuals nearest 0 is
    // within the tolerance and the two forces are too, the window ends in
    // that blend of the two, as the 1D stepper's does. Where the blend
    // settles but the forces are apart and the quasi-Newton steps have
    // stopped improving, the two are brought together by bisection, each
    // new pass taking the place of the kept one on its side.
    bool blended = false;
    for (int side = 0; passes > 1 && side < (bisecting ? 2 : 1) && !blended; ++side) {
      const Straddle st = straddle(w, w.kept[side], scale);
      blended = st.across() && st.blend_settles && st.close &&
                blend_passes(m, s, w, w.kept[side], st.theta, taken, work_by_particles);
    }
    if (blended) {
      status |= pass;
      s.blended_windows += 1;
      break;
    }
    if (bisecting) {
      if (straddle(w, w.kept[0], scale).across()) {
        keep_pass(m, s, w, w.kept[1], scale, taken, work_by_particles);
      } else if (straddle(w, w.kept[1], scale).across()) {
        keep_pass(m, s, w, w.kept[0], scale, taken, work_by_particles);
      } else {
        bisecting = false;
      }
    } else if (passes > 1 && !last_is_best) {  // no progress: a jump, not a root between them
      const Straddle st = straddle(w, w.kept[0], scale);
      if (st.across() && st.blend_settles) {
        bisecting = true;
        keep_pass(m, s, w, w.kept[1], scale, taken, work_by_particles);
      }
    }
    if (bisecting && passes < kCoupled2dMaxPasses) {
      best_pass = passes;  // bisection halves the gap: not a stall
      for (std::size_t k = 0; k < dofs; ++k) force[k] = 0.5 * (w.kept[0].force[k] + w.kept[1].force[k]);
      continue;
    }
    // A jump that no two passes straddle closely enough: the passes circle
    // it, and the window takes the pass with the smallest residual.
    if (passes - best_pass >= kCoupled2dStallPasses || passes == kCoupled2dMaxPasses) {
      if (!last_is_best) {
        force = w.best_force;
        pass = window_pass(m, s, w, taken, work_by_particles);
        ++passes;
      }
      status |= pass;
      s.unsettled_windows += 1;
      s.worst_unsettled = std::max(s.worst_unsettled, best);
      if (!(best <= kCoupled2dJumpTolerance)) status |= StepStatus::coupling_unstable;
      break;
    }
    // A quasi-Newton step that made the residual much worse than the best
    // (its secant model spans a kink of the window map): forget the history
    // and start again from the best pass, by Picard steps first.
    if (passes > 1 && columns > 0 && g > kCoupled2dRestartGrowth * best) {
      columns = 0, newest = -1;
      force = w.best_force;
      restarted = true;
      continue;
    }
    // The quasi-Newton's column of this pass against the last (none right
    // after a restart: the last pass is the one forgotten), then its step.
    if (passes > 1 && !restarted) {
      newest = (newest + 1) % kCoupled2dHistory;
      columns = std::min(columns + 1, kCoupled2dHistory);
      double* dr = w.history_residual.data() + static_cast<std::size_t>(newest) * dofs;
      double* dh = w.history_output.data() + static_cast<std::size_t>(newest) * dofs;
      for (std::size_t k = 0; k < dofs; ++k) {
        dr[k] = w.residual[k] - w.previous_residual[k];
        dh[k] = w.impulse[k] / m.dt - w.previous_output[k];
      }
    }
    for (std::size_t k = 0; k < dofs; ++k) {
      w.previous_residual[k] = w.residual[k];
      w.previous_output[k] = w.impulse[k] / m.dt;
    }
    restarted = false;
    keep_pass(m, s, w, w.kept[0], scale, taken, work_by_particles);
    quasi_newton_step(w, columns, newest, force);
  }
  // The plate takes the impulse the disks gave in the last pass, exactly.
  bool exact = true;
  for (std::size_t k = 0; k < dofs; ++k) exact = exact && force[k] == w.impulse[k] / m.dt;
  if (!exact) {
    for (std::size_t k = 0; k < dofs; ++k) force[k] = w.impulse[k] / m.dt;
    s.plate = w.plate_start;
    status |= plate_start_acceleration(m.plate, s.plate, w.plate);
    status |= without(plate_step(m.plate, s.plate, w.plate), StepStatus::energy_growth);
  }
  double work = 0;
  for (std::size_t k = 0; k < dofs; ++k) work += force[k] * (s.plate.u[k] - w.plate_start.u[k]);
  s.work_on_plate += work;
  s.work_by_particles += work_by_particles;
  s.coupling_force = force;
  for (int axis = 0; axis < 2; ++axis) {
    s.impulse_to_particles[axis] += taken[axis];
    s.impulse_to_plate[axis] += m.dt * translation_share(m.plate, force, axis);
  }
  s.last_passes = passes;
  s.peak_passes = std::max(s.peak_passes, passes);
  s.step += 1;
  s.time = static_cast<double>(s.step) * m.dt;
  if (m.beyond_stable_step) status |= StepStatus::unstable_time_step;
  s.energy.work += (s.plate.energy.work + s.dem.energy.work) - booked_before;
  if (energy_check_due(m.energy_check, s.step))
    energy_check(s.energy, m.energy_check, coupled2d_energy_totals(m, s, w.positions.data()));
  if (s.energy.exceeded != 0) status |= StepStatus::energy_growth;
  return status;
}

bool coupled2d_boundary_force(const Coupled2dModel& m, const Coupled2dState& s, std::int32_t i, double force[2]) {
  force[0] = force[1] = 0.0;
  if (i < 0 || i >= m.dem.n) return false;
  // Symplectic Euler: the step leaves each disk's boundary force as its
  // external force input; the others: the hook's last evaluation.
  const auto& source = hooked(m) ? s.boundary_force : s.dem.external_force;
  force[0] = source[0][static_cast<std::size_t>(i)];
  force[1] = source[1][static_cast<std::size_t>(i)];
  return true;
}

double coupled2d_boundary_energy(const Coupled2dModel& m, const Coupled2dState& s, double* positions) {
  if (!m.built) return 0.0;
  plate_boundary_positions(m.plate, m.boundary, s.plate.u.data(), s.plate.time, positions);
  const bool hertz = m.dem.law == ContactLaw::hertz;
  // Linear friction: ½ k_t |ξ|² of the kept springs, each up to the Coulomb
  // cap of its contact's normal spring (tangential_energy), the contact the
  // spring's own as the step matches them: its chain, the nearest normal
  // within 60° (rotating_contacts).
  const bool springs = m.rotating && !hertz && m.dem.friction > 0;
  // The springs' x and y components, interleaved (none without friction).
  const double* const xi[2] = {s.springs.xi.data(), springs ? s.springs.xi.data() + 1 : nullptr};
  double energy = 0;
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double centre[2] = {s.dem.x[0][iu], s.dem.x[1][iu]};
    PlateBoundaryContact c[kPlateBoundaryMaxContacts];
    const int count = plate_boundary_contacts(m.boundary, positions, centre, m.dem.radius[iu], c);
    for (int k = 0; k < count; ++k)
      energy += hertz ? dem_detail::hertz_energy(1.0 / (m.dem.hertz_inv_e[iu] + m.plate_inv_e), m.dem.radius[iu],
                                                 c[k].overlap)
                      : dem_detail::spring_energy(m.dem.stiffness[iu], c[k].overlap);
    if (!springs) continue;
    for (int k = 0; k < kPlateBoundaryMaxContacts; ++k) {
      const std::size_t slot = iu * kPlateBoundaryMaxContacts + static_cast<std::size_t>(k);
      if (s.springs.chain[slot] < 0) continue;
      double overlap = 0, nearest = 0.5;
      for (int q = 0; q < count; ++q) {
        if (m.boundary.segments[static_cast<std::size_t>(c[q].segment)].chain != s.springs.chain[slot]) continue;
        const double cosine =
            s.springs.normal[2 * slot] * c[q].normal[0] + s.springs.normal[2 * slot + 1] * c[q].normal[1];
        if (cosine > nearest) nearest = cosine, overlap = c[q].overlap;
      }
      energy += dem_detail::tangential_energy<2>(m.dem.tangential_ratio * m.dem.stiffness[iu], xi, 2 * slot,
                                                 m.dem.friction * m.dem.stiffness[iu] * overlap);
    }
  }
  return energy;
}

EnergyTotals coupled2d_energy_totals(const Coupled2dModel& m, const Coupled2dState& s, double* positions) {
  if (!m.built) return {};
  const DemEnergy dem = dem_energy(m.dem, s.dem);
  const double boundary = coupled2d_boundary_energy(m, s, positions);
  const double plate = plate_algorithmic_energy(m.plate, s.plate);
  const double in_motion = dem.kinetic + dem.elastic + boundary + plate;
  return {in_motion + dem.potential, in_motion, in_motion + std::fabs(dem.potential)};
}

void coupled2d_restart_energy_ledger(const Coupled2dModel& m, Coupled2dState& s, Coupled2dWorkspace& w) {
  if (!m.built) return;
  energy_restart(s.energy, coupled2d_energy_totals(m, s, w.positions.data()));
}

}  // namespace xfdem
