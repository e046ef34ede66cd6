// The scene file's `continuum` block (shared spec: scenes.md) -> xfdem::BarDesc.
#pragma once
#include "scene/json_reader.hpp"
#include "xfdem/bar.hpp"

namespace xfdem::scene {

/// Reads exactly the keys of a `continuum` block:
///   type ("bar"), method (xfem | fem), length, youngs_modulus, area, density,
///   elements, base (fixed | absorbing), base_stiffness (absorbing only, default 0),
///   interface { position, stiffness, behaviour (tied | unilateral) } (optional),
///   newmark { beta, gamma } (required),
///   tip_load { shape (none | half_sine | step), amplitude, duration (half_sine only) } (optional).
/// `dt` is the scene's time.dt (the continuum step). Unknown keys and bad values
/// throw SceneError naming the dotted key, e.g.
///   scene key 'continuum.interface.position': must lie strictly inside the bar (0, 30) m (got 31)
BarDesc parse_continuum(ObjectReader& continuum, double dt);

}  // namespace xfdem::scene
