// `xfdem run SCENE --vtk DIR` (scenes-2d.md, "Output for viewing"): at every
// output sample, the plate and the particles as VTK XML unstructured grids
// (ASCII), and DIR/<scene name>.pvd, the collection ParaView opens in one go.
//
//   DIR/<name>_plate_<k>.vtu      the deformed plate (points at x + u), one
//                                 VTK cell per piece the plate writes
//                                 (for_each_plate_piece); point data
//                                 displacement, velocity; cell data
//                                 stress_xx, stress_yy, stress_xy and
//                                 von_mises at the piece's centroid
//   DIR/<name>_particles_<k>.vtu  one vertex per particle at its position;
//                                 point data radius, velocity, angular_velocity
//   DIR/<name>.pvd                every sample's files at its time (part 0 the
//                                 plate, part 1 the particles)
//
// k counts the samples from 0 (six digits, more when needed). Written by hand
// (the format is plain XML), so the tools need no VTK library; the kernel
// knows nothing of it.
#pragma once
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "scene/scene.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/plate.hpp"

namespace xfdem::scene {

/// One piece of the plate as it is written: a polygon with its corners
/// counter-clockwise, the fields at each corner as seen from the piece, and
/// the stress at its centroid. An uncut cell is one piece (its four nodes); a
/// cut cell is its triangles on each material side (plate_cell_pieces()), each
/// with its own side's values at its corners, so that a crack opens in the
/// picture; nothing is written in a void.
struct PlatePiece {
  static constexpr int kMaxCorners = 8;
  int corners = 0;
  double reference[kMaxCorners][2] = {};  ///< undeformed corner positions, m
  double u[kMaxCorners][2] = {};          ///< displacement at each corner, m
  double v[kMaxCorners][2] = {};          ///< velocity at each corner, m/s
  double stress[3] = {};                  ///< σ_xx, σ_yy, σ_xy at the centroid, Pa
};

/// Visits the pieces to write, cell by cell (i fastest).
void for_each_plate_piece(const PlateModel& model, const PlateState& state, void (*visit)(const PlatePiece&, void*),
                          void* context);
template <class Visit>
void for_each_plate_piece(const PlateModel& model, const PlateState& state, Visit&& visit) {
  using F = std::remove_reference_t<Visit>;
  for_each_plate_piece(
      model, state, [](const PlatePiece& piece, void* f) { (*static_cast<F*>(f))(piece); },
      const_cast<void*>(static_cast<const void*>(&visit)));
}

/// Von Mises stress of the plate's in-plane stress (σ_zz = 0 in plane stress,
/// ν (σ_xx + σ_yy) in plane strain), Pa.
double plate_von_mises(const PlateModel& model, const double stress[3]);

/// Throws the SceneError of a scene --vtk cannot write: one with a bar (the
/// bar, alone or with particles, has no VTK output).
void require_vtk_output(const Scene& scene);

/// The files of one run. Construction creates DIR (and its parents) when
/// missing and checks a file can be written in it; failures are SceneErrors
/// naming --vtk, the path and the reason. A run calls sample(t), then plate()
/// and/or particles(), at every output time, and finish() at the end; a failed
/// run calls abandon(), which removes every file written.
class VtkSeries {
 public:
  /// Checks the scene (require_vtk_output) before touching the directory.
  VtkSeries(const std::string& directory, const Scene& scene);
  /// Starts the sample at time t (s).
  void sample(double t);
  void plate(const PlateModel& model, const PlateState& state);
  template <int D>
  void particles(const DemModel<D>& model, const DemState<D>& state);
  /// Writes the .pvd (to .pvd.partial, renamed into place once written).
  void finish();
  /// Removes the files written so far.
  void abandon();
  [[nodiscard]] const std::string& pvd_path() const { return pvd_; }

 private:
  struct Entry {
    double time;
    int part;
    std::string file;  ///< relative to the directory
  };
  void write_file(const std::string& name, const std::string& text);
  [[nodiscard]] std::string file_name(const char* what) const;

  std::string directory_, name_, pvd_;
  std::int64_t sample_ = -1;
  double time_ = 0.0;
  std::vector<Entry> entries_;
  std::vector<std::string> written_;
};

}  // namespace xfdem::scene
