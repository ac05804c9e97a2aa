#include "cloth_sim/core/model/mesh_builder.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace cloth_sim {

BuiltObject buildMeshObject(const MeshSpec& spec) {
  validateClothSurface(spec.mesh, spec.source);
  auto positive = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!(std::isfinite(spec.areal_density) && spec.areal_density > 0.0)) {
    throw std::invalid_argument(spec.source + ": areal_density must be finite and > 0 kg/m^2");
  }
  if ((spec.has_structural && !positive(spec.structural)) ||
      (spec.has_bending && !positive(spec.bending))) {
    throw std::invalid_argument(spec.source + ": spring stiffness must be finite and >= 0 N/m");
  }
  const TriangleMesh& mesh = spec.mesh;
  BuiltObject out;
  out.rest_positions = mesh.vertices;
  Model& model = out.model;
  model.triangles = mesh.triangles;
  model.mass = Eigen::VectorXd::Zero(mesh.vertexCount());

  // Edge -> the vertices opposite it in its (one or two) triangles.
  std::map<std::pair<int, int>, std::vector<int>> opposite;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const double third = spec.areal_density * mesh.triangleArea(t) / 3.0;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(k, t), b = mesh.triangles((k + 1) % 3, t);
      const int c = mesh.triangles((k + 2) % 3, t);
      model.mass[a] += third;
      opposite[{std::min(a, b), std::max(a, b)}].push_back(c);
    }
  }
  auto add = [&](int i, int j, double k, SpringFamily family) {
    model.springs.add(i, j, (mesh.vertices.col(i) - mesh.vertices.col(j)).norm(), k, family);
  };
  for (const auto& [edge, across] : opposite) {
    if (spec.has_structural) add(edge.first, edge.second, spec.structural, SpringFamily::kStructural);
    if (spec.has_bending && across.size() == 2 && across[0] != across[1] &&
        (mesh.vertices.col(across[0]) - mesh.vertices.col(across[1])).norm() > 0.0) {
      add(across[0], across[1], spec.bending, SpringFamily::kBending);
    }
  }
  return out;
}

}  // namespace cloth_sim
