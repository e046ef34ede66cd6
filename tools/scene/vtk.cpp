#include "scene/vtk.hpp"

#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "scene/json_reader.hpp"

namespace xfdem::scene {
namespace {

namespace fs = std::filesystem;

/// Shortest text that reads back to the same double (std::to_chars).
void put(std::string& out, double value) {
  char text[32];
  const std::to_chars_result r = std::to_chars(text, text + sizeof(text), value);
  out.append(text, r.ptr);
}

void put(std::string& out, std::int64_t value) {
  char text[24];
  const std::to_chars_result r = std::to_chars(text, text + sizeof(text), value);
  out.append(text, r.ptr);
}

/// Text for an XML attribute value.
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  return out;
}

// Node coordinate i of nc cells on [lo, hi], as the plate's mesh places it
// (the last node exactly at hi).
double node_coord(double lo, double hi, int i, int nc) { return i == nc ? hi : lo + (hi - lo) * i / nc; }

/// A nodal displacement (displacement) or velocity of the state (held
/// components: their displacement at the state's time, and 0 for the
/// velocity unless a prescribed shape moves them).
double nodal(const PlateModel& m, const PlateState& s, bool displacement, int node, int c) {
  const auto k = static_cast<std::size_t>(2 * node + c);
  const int dof = m.node_dof[k];
  if (dof >= 0) return (displacement ? s.u : s.v)[static_cast<std::size_t>(dof)];
  const int h = m.node_moving.empty() ? -1 : m.node_moving[k];
  if (h < 0) return displacement ? m.node_held[k] : 0.0;
  const auto hh = static_cast<std::size_t>(h);
  return displacement ? m.moving_amplitude[hh] * plate_prescribed_shape(m, m.moving_prescribed[hh], s.time)
                      : s.held_v[hh];
}

const char* kHeader =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
    "  <UnstructuredGrid>\n";
const char* kFooter = "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";

void open_array(std::string& out, const char* type, const char* name, int components) {
  out += "        <DataArray type=\"";
  out += type;
  out += '"';
  if (name != nullptr) {
    out += " Name=\"";
    out += name;
    out += '"';
  }
  out += " NumberOfComponents=\"";
  put(out, static_cast<std::int64_t>(components));
  out += "\" format=\"ascii\">\n";
}
void close_array(std::string& out) { out += "\n        </DataArray>\n"; }

/// A Float64 array of n tuples of `components` values, value(i, c).
template <class Value>
void float_array(std::string& out, const char* name, int components, std::size_t n, Value&& value) {
  open_array(out, "Float64", name, components);
  for (std::size_t i = 0; i < n; ++i) {
    out += i == 0 ? "          " : "\n          ";
    for (int c = 0; c < components; ++c) {
      if (c > 0) out += ' ';
      put(out, value(i, c));
    }
  }
  close_array(out);
}

/// The cells block: each cell's corners are consecutive points.
void cells(std::string& out, const std::vector<int>& corners, bool vertices) {
  out += "      <Cells>\n";
  open_array(out, "Int64", "connectivity", 1);
  std::int64_t point = 0;
  out += "          ";
  for (int count : corners)
    for (int c = 0; c < count; ++c) {
      if (point > 0) out += ' ';
      put(out, point++);
    }
  close_array(out);
  open_array(out, "Int64", "offsets", 1);
  out += "          ";
  std::int64_t end = 0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (k > 0) out += ' ';
    end += corners[k];
    put(out, end);
  }
  close_array(out);
  open_array(out, "UInt8", "types", 1);
  out += "          ";
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (k > 0) out += ' ';
    // VTK_VERTEX 1, VTK_TRIANGLE 5, VTK_QUAD 9, VTK_POLYGON 7.
    put(out, static_cast<std::int64_t>(vertices ? 1 : corners[k] == 3 ? 5 : corners[k] == 4 ? 9 : 7));
  }
  close_array(out);
  out += "      </Cells>\n";
}

void piece_header(std::string& out, std::size_t points, std::size_t cell_count) {
  out += kHeader;
  out += "    <Piece NumberOfPoints=\"";
  put(out, static_cast<std::int64_t>(points));
  out += "\" NumberOfCells=\"";
  put(out, static_cast<std::int64_t>(cell_count));
  out += "\">\n";
}

}  // namespace

// ---- the plate's pieces ---------------------------------------------------------

void for_each_plate_piece(const PlateModel& m, const PlateState& s, void (*visit)(const PlatePiece&, void*),
                          void* context) {
  if (!m.built) return;
  const PlateDesc& d = m.desc;
  const int nx = d.cells[0], ny = d.cells[1];
  // Corners counter-clockwise from the lower left, as the element's nodes.
  constexpr int kDi[4] = {0, 1, 1, 0}, kDj[4] = {0, 0, 1, 1};
  PlatePiece piece;
  if (!m.node_phi.empty()) {
    // With discontinuities: the cells' pieces as the plate integrates them
    // (an uncut cell whole, a cut cell's triangles of each material side),
    // each with the enriched field of its own side.
    PlateCellPiece cell[kPlateMaxCellPieces];
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x0 = node_coord(d.min[0], d.max[0], i, nx), x1 = node_coord(d.min[0], d.max[0], i + 1, nx);
        const double y0 = node_coord(d.min[1], d.max[1], j, ny), y1 = node_coord(d.min[1], d.max[1], j + 1, ny);
        const int count = plate_cell_pieces(m, i, j, cell);
        for (int p = 0; p < count; ++p) {
          const PlateCellPiece& q = cell[p];
          piece.corners = q.corners;
          double xi = 0.0, eta = 0.0, unused[3];
          for (int a = 0; a < q.corners; ++a) {
            piece.reference[a][0] = x0 + 0.5 * (1.0 + q.xi[a]) * (x1 - x0);
            piece.reference[a][1] = y0 + 0.5 * (1.0 + q.eta[a]) * (y1 - y0);
            plate_piece_fields(m, s, i, j, q, q.xi[a], q.eta[a], piece.u[a], piece.v[a], unused);
            xi += q.xi[a] / q.corners, eta += q.eta[a] / q.corners;
          }
          double rate[2];
          plate_piece_fields(m, s, i, j, q, xi, eta, unused, rate, piece.stress);
          visit(piece, context);
        }
      }
    return;
  }
  piece.corners = 4;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      for (int a = 0; a < 4; ++a) {
        const int ia = i + kDi[a], ja = j + kDj[a];
        const int node = ja * (nx + 1) + ia;
        piece.reference[a][0] = node_coord(d.min[0], d.max[0], ia, nx);
        piece.reference[a][1] = node_coord(d.min[1], d.max[1], ja, ny);
        for (int c = 0; c < 2; ++c) {
          piece.u[a][c] = nodal(m, s, true, node, c);
          piece.v[a][c] = nodal(m, s, false, node, c);
        }
      }
      const double xc = 0.5 * (piece.reference[0][0] + piece.reference[1][0]);
      const double yc = 0.5 * (piece.reference[0][1] + piece.reference[3][1]);
      for (int c = 0; c < 3; ++c) piece.stress[c] = plate_stress(m, s, xc, yc, c);
      visit(piece, context);
    }
}

double plate_von_mises(const PlateModel& m, const double stress[3]) {
  const double sxx = stress[0], syy = stress[1], sxy = stress[2];
  const double szz = m.desc.plane == PlateDesc::Plane::strain ? m.desc.poisson_ratio * (sxx + syy) : 0.0;
  return std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
                   3.0 * sxy * sxy);
}

// ---- the series -------------------------------------------------------------------

void require_vtk_output(const Scene& scene) {
  if (scene.bar) throw SceneError("--vtk: writes plates and particles; this scene has a bar, which has no VTK output");
}

VtkSeries::VtkSeries(const std::string& directory, const Scene& scene) : directory_(directory), name_(scene.name) {
  require_vtk_output(scene);
  if (directory.empty()) throw SceneError("--vtk: must name a directory (got an empty path)");
  if (name_.empty() || name_ == "." || name_ == ".." || name_.find('/') != std::string::npos)
    throw SceneError("--vtk: the scene's name '" + name_ + "' cannot name a file (scene key 'name')");
  std::error_code ec;
  const fs::file_status status = fs::status(directory, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw SceneError("--vtk '" + directory + "': exists and is not a directory");
  if (!fs::exists(status)) {
    fs::create_directories(directory, ec);
    if (ec) throw SceneError("--vtk '" + directory + "': cannot create the directory: " + ec.message());
  }
  pvd_ = (fs::path(directory) / (name_ + ".pvd")).string();
  // Whether a file can be written there: the collection's temporary file.
  const std::string probe = pvd_ + ".partial";
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (f == nullptr)
    throw SceneError("--vtk '" + directory + "': cannot write in the directory: " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
}

void VtkSeries::sample(double t) {
  ++sample_;
  time_ = t;
}

std::string VtkSeries::file_name(const char* what) const {
  char number[32];
  std::snprintf(number, sizeof(number), "%06lld", static_cast<long long>(sample_));
  return name_ + "_" + what + "_" + number + ".vtu";
}

void VtkSeries::write_file(const std::string& name, const std::string& text) {
  const std::string path = (fs::path(directory_) / name).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  int error = f == nullptr ? errno : 0;
  if (f != nullptr) {
    written_.push_back(path);
    if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) error = errno;
    if (std::fclose(f) != 0 && error == 0) error = errno;
  }
  if (error != 0) throw SceneError("--vtk: cannot write '" + path + "': " + std::strerror(error));
}

void VtkSeries::plate(const PlateModel& model, const PlateState& state) {
  std::vector<PlatePiece> pieces;
  for_each_plate_piece(model, state, [&](const PlatePiece& p) { pieces.push_back(p); });
  std::vector<int> corners;
  std::size_t points = 0;
  for (const PlatePiece& p : pieces) {
    corners.push_back(p.corners);
    points += static_cast<std::size_t>(p.corners);
  }
  // Point k of the file: corner `corner[k]` of piece `owner[k]`.
  std::vector<std::pair<std::size_t, int>> at;
  at.reserve(points);
  for (std::size_t k = 0; k < pieces.size(); ++k)
    for (int c = 0; c < pieces[k].corners; ++c) at.emplace_back(k, c);
  auto field = [&](double(PlatePiece::*f)[PlatePiece::kMaxCorners][2]) {
    return [&, f](std::size_t i, int c) { return c < 2 ? (pieces[at[i].first].*f)[at[i].second][c] : 0.0; };
  };
  std::string out;
  piece_header(out, points, pieces.size());
  out += "      <PointData Vectors=\"displacement\">\n";
  float_array(out, "displacement", 3, points, field(&PlatePiece::u));
  float_array(out, "velocity", 3, points, field(&PlatePiece::v));
  out += "      </PointData>\n      <CellData Scalars=\"von_mises\">\n";
  const char* names[3] = {"stress_xx", "stress_yy", "stress_xy"};
  for (int s = 0; s < 3; ++s)
    float_array(out, names[s], 1, pieces.size(), [&](std::size_t i, int) { return pieces[i].stress[s]; });
  float_array(out, "von_mises", 1, pieces.size(),
              [&](std::size_t i, int) { return plate_von_mises(model, pieces[i].stress); });
  out += "      </CellData>\n      <Points>\n";
  float_array(out, nullptr, 3, points, [&](std::size_t i, int c) {
    const PlatePiece& p = pieces[at[i].first];
    return c < 2 ? p.reference[at[i].second][c] + p.u[at[i].second][c] : 0.0;
  });
  out += "      </Points>\n";
  cells(out, corners, false);
  out += kFooter;
  const std::string name = file_name("plate");
  write_file(name, out);
  entries_.push_back({time_, 0, name});
}

template <int D>
void VtkSeries::particles(const DemModel<D>& model, const DemState<D>& state) {
  const auto n = static_cast<std::size_t>(model.n);
  std::string out;
  piece_header(out, n, n);
  out += "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  float_array(out, "radius", 1, n, [&](std::size_t i, int) { return model.radius[i]; });
  float_array(out, "velocity", 3, n, [&](std::size_t i, int c) { return c < D ? state.v[static_cast<std::size_t>(c)][i] : 0.0; });
  // A frictionless model does not rotate (no spin arrays): its angular velocity is zero.
  float_array(out, "angular_velocity", 3, n, [&](std::size_t i, int c) {
    if constexpr (D == 1) {
      return 0.0;
    } else {
      const int k = D == 2 ? c - 2 : c;  // 2D: the spin is about z
      return k >= 0 && !state.w[static_cast<std::size_t>(k)].empty() ? state.w[static_cast<std::size_t>(k)][i] : 0.0;
    }
  });
  out += "      </PointData>\n      <Points>\n";
  float_array(out, nullptr, 3, n, [&](std::size_t i, int c) { return c < D ? state.x[static_cast<std::size_t>(c)][i] : 0.0; });
  out += "      </Points>\n";
  cells(out, std::vector<int>(n, 1), true);
  out += kFooter;
  const std::string name = file_name("particles");
  write_file(name, out);
  entries_.push_back({time_, 1, name});
}

template void VtkSeries::particles<1>(const DemModel<1>&, const DemState<1>&);
template void VtkSeries::particles<2>(const DemModel<2>&, const DemState<2>&);
template void VtkSeries::particles<3>(const DemModel<3>&, const DemState<3>&);

void VtkSeries::finish() {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const Entry& e : entries_) {
    out += "    <DataSet timestep=\"";
    put(out, e.time);
    out += "\" group=\"\" part=\"";
    put(out, static_cast<std::int64_t>(e.part));
    out += "\" file=\"" + escaped(e.file) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  const std::string partial = name_ + ".pvd.partial";
  write_file(partial, out);
  std::error_code ec;
  fs::rename(fs::path(directory_) / partial, pvd_, ec);
  if (ec) throw SceneError("--vtk: cannot move the collection into '" + pvd_ + "': " + ec.message());
  written_.back() = pvd_;
}

void VtkSeries::abandon() {
  for (const std::string& path : written_) std::remove(path.c_str());
  written_.clear();
  entries_.clear();
}

}  // namespace xfdem::scene
