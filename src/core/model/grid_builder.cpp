#include "cloth_sim/core/model/grid_builder.h"

#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

void GridSpec::validate() const {
  settings::kGridResolution.require(rows);
  settings::kGridResolution.require(cols);
  settings::kGridSize.require(width);
  settings::kGridSize.require(height);
  if (!pose.matrix().allFinite()) throw std::invalid_argument("grid pose must be finite");
  material.validate();
}

BuiltObject buildGrid(const GridSpec& spec) {
  spec.validate();
  const int rows = spec.rows, cols = spec.cols, n = rows * cols;
  const double dx = spec.width / (cols - 1), dy = spec.height / (rows - 1);
  const Material& m = spec.material;

  BuiltObject out;
  Model& model = out.model;
  out.rest_positions.resize(3, n);
  model.mass.resize(n);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Vec3 local(-0.5 * spec.width + c * dx, 0.5 * spec.height - r * dy, 0.0);
      out.rest_positions.col(gridVertex(r, c, cols)) = spec.pose * local;
      const double share_x = (c == 0 || c == cols - 1) ? 0.5 : 1.0;
      const double share_y = (r == 0 || r == rows - 1) ? 0.5 : 1.0;
      model.mass[gridVertex(r, c, cols)] = m.areal_density * dx * dy * share_x * share_y;
    }
  }

  auto add = [&](int r0, int c0, int r1, int c1, double k, SpringFamily f) {
    const int i = gridVertex(r0, c0, cols), j = gridVertex(r1, c1, cols);
    model.springs.add(i, j, (out.rest_positions.col(i) - out.rest_positions.col(j)).norm(), k, f);
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (m.has_structural) {
        if (c + 1 < cols) add(r, c, r, c + 1, m.structural, SpringFamily::kStructural);
        if (r + 1 < rows) add(r, c, r + 1, c, m.structural, SpringFamily::kStructural);
      }
      if (m.has_shear && r + 1 < rows && c + 1 < cols) {
        add(r, c, r + 1, c + 1, m.shear, SpringFamily::kShear);
        if (spec.shear_pattern == ShearPattern::kBoth) {
          add(r, c + 1, r + 1, c, m.shear, SpringFamily::kShear);
        }
      }
      if (m.has_bending) {
        if (c + 2 < cols) add(r, c, r, c + 2, m.bending, SpringFamily::kBending);
        if (r + 2 < rows) add(r, c, r + 2, c, m.bending, SpringFamily::kBending);
      }
    }
  }

  // Two counter-clockwise (local +z normal) triangles per quad, split along (r,c)-(r+1,c+1).
  model.triangles.resize(3, 2 * (rows - 1) * (cols - 1));
  int t = 0;
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      const int v00 = gridVertex(r, c, cols), v01 = gridVertex(r, c + 1, cols);
      const int v10 = gridVertex(r + 1, c, cols), v11 = gridVertex(r + 1, c + 1, cols);
      model.triangles.col(t++) << v00, v10, v11;
      model.triangles.col(t++) << v00, v11, v01;
    }
  }
  return out;
}

}  // namespace cloth_sim
