#include "cloth_sim/core/model/mesh_builder.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace cloth_sim {

BuiltObject buildMeshObject(const MeshSpec& spec) {
  validateClothSurface(spec.mesh, spec.source);
  const Material& m = spec.material;
  m.validate();
  if (m.has_shear) {
    throw std::invalid_argument(spec.source + ": a mesh cloth has no shear springs (has_shear)");
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
    const double third = m.areal_density * mesh.triangleArea(t) / 3.0;
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
    if (m.has_structural) add(edge.first, edge.second, m.structural, SpringFamily::kStructural);
    if (m.has_bending && across.size() == 2 && across[0] != across[1] &&
        (mesh.vertices.col(across[0]) - mesh.vertices.col(across[1])).norm() > 0.0) {
      add(across[0], across[1], m.bending, SpringFamily::kBending);
    }
  }
  return out;
}

}  // namespace cloth_sim
