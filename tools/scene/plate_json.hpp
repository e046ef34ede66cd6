// The scene file's 2D continuum, `"continuum": {"type": "plate", ...}`
// (shared spec: scenes-2d.md) -> xfdem::PlateDesc, and the plate's probes.
// Discontinuities: cracks (faces free, tied or unilateral; a crack ending
// inside the plate has a tip, its faces free), inclusions and voids;
// tip_enrichment { radius } and the `stress_intensity` probe.
#pragma once
#include <vector>

#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "xfdem/plate.hpp"

namespace xfdem::scene {

/// True when the document's continuum block is a plate with "analysis": "static"
/// (such a scene needs no `time` block and no `output.every`).
bool is_static_plate(const Json& document);

/// Reads exactly the keys of a plate block: type ("plate"), plane (strain |
/// stress, default strain), thickness (default 1), domain { min, max },
/// cells [nx, ny], material { youngs_modulus, poisson_ratio, density },
/// self_weight (default false; uses the scene's gravity), tip_enrichment
/// { radius } (m, >= 0, default 0: the nodes of the tip's cell), analysis (dynamic |
/// static, default dynamic), newmark { beta, gamma } (default 1/4, 1/2),
/// supports [ { edge, fix: [x, y], absorbing } ], prescribed [ { at, displacement } ],
/// loads [ { edge, traction, shape, duration } | { at, force, shape, duration } ],
/// discontinuities [ { name, type: crack, points, faces, stiffness } |
/// { name, type: inclusion | void, circle { centre, radius } | polygon, material } ].
/// `dt` is the scene's time.dt (0 for a static scene without a time block).
/// Unknown keys and bad values throw SceneError naming the dotted key.
PlateDesc parse_plate(ObjectReader& continuum, double dt, const std::vector<double>& gravity);

/// Reads one probe of a plate scene (after its name): `quantity` displacement |
/// velocity | acceleration (at [x, y], component 0 | 1), stress (at, component
/// xx | yy | xy), energy (of total | kinetic | elastic | potential), momentum
/// (of total | continuum | particles, component 0 | 1), crack_opening (crack,
/// at a point on it, component normal | tangential). A point on a
/// discontinuity or in a void is refused for the fields at a point.
void parse_plate_probe(ObjectReader& probe_object, const PlateDesc& plate, Probe& probe);

}  // namespace xfdem::scene
