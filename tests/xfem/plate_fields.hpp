// Test helper: set a plate's nodal field from a function of position.
#pragma once
#include <vector>

#include "xfdem/plate.hpp"

namespace xfdem::test {

/// Sets every free nodal component (standard unknowns only) from f(x, y, c).
template <class F>
void set_field(const PlateModel& m, std::vector<double>& field, F&& f) {
  const PlateDesc& d = m.desc;
  for (int j = 0; j <= d.cells[1]; ++j)
    for (int i = 0; i <= d.cells[0]; ++i) {
      const int n = j * (d.cells[0] + 1) + i;
      const double x = i == d.cells[0] ? d.max[0] : d.min[0] + (d.max[0] - d.min[0]) * i / d.cells[0];
      const double y = j == d.cells[1] ? d.max[1] : d.min[1] + (d.max[1] - d.min[1]) * j / d.cells[1];
      for (int c = 0; c < 2; ++c) {
        const int dof = m.node_dof[static_cast<std::size_t>(2 * n + c)];
        if (dof >= 0) field[static_cast<std::size_t>(dof)] = f(x, y, c);
      }
    }
}

}  // namespace xfdem::test
