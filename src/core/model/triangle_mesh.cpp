#include "cloth_sim/core/model/triangle_mesh.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <tiny_obj_loader.h>

namespace cloth_sim {

double TriangleMesh::triangleArea(int t) const {
  const Vec3 a = vertices.col(triangles(0, t)), b = vertices.col(triangles(1, t)),
             c = vertices.col(triangles(2, t));
  return 0.5 * (b - a).cross(c - a).norm();
}

TriangleMesh TriangleMesh::transformed(const Eigen::Isometry3d& pose, double scale) const {
  TriangleMesh out = *this;
  out.vertices = pose * (scale * vertices);
  return out;
}

TriangleMesh parseObj(const std::string& text, const std::string& source) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, "", config)) {
    throw std::invalid_argument(source + ": OBJ parse error: " + reader.Error());
  }
  const auto& positions = reader.GetAttrib().vertices;
  TriangleMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(positions.size() / 3));
  for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
    for (int a = 0; a < 3; ++a) mesh.vertices(a, v) = positions[3 * v + a];
  }
  std::vector<Eigen::Vector3i> faces;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
      faces.emplace_back(indices[f].vertex_index, indices[f + 1].vertex_index,
                         indices[f + 2].vertex_index);
    }
  }
  if (faces.empty()) throw std::invalid_argument(source + ": OBJ has no face");
  mesh.triangles.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (std::size_t t = 0; t < faces.size(); ++t) mesh.triangles.col(t) = faces[t];
  return mesh;
}

TriangleMesh loadObj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open the OBJ file");
  std::stringstream text;
  text << in.rdbuf();
  return parseObj(text.str(), path);
}

void validateClothSurface(const TriangleMesh& mesh, const std::string& source) {
  const int n = mesh.vertexCount();
  auto fail = [&](const std::string& what) { throw std::invalid_argument(source + ": " + what); };
  if (mesh.triangleCount() == 0) fail("mesh has no triangle");
  if (!mesh.vertices.allFinite()) fail("mesh has a non-finite vertex coordinate");
  if (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= n) {
    fail("a triangle refers to a vertex index out of range [0, " + std::to_string(n) + ")");
  }
  const double diagonal2 =
      (mesh.vertices.rowwise().maxCoeff() - mesh.vertices.rowwise().minCoeff()).squaredNorm();
  std::vector<char> used(n, 0);
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Eigen::Vector3i f = mesh.triangles.col(t);
    auto name = [&] {  // built only for an error message
      return "triangle " + std::to_string(t) + " (" + std::to_string(f[0]) + ", " +
             std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")";
    };
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) fail(name() + " repeats a vertex");
    const double area = mesh.triangleArea(t);
    if (!(area > 1e-12 * diagonal2)) {
      std::ostringstream msg;
      msg << name() << " is degenerate (area " << area << " m^2)";
      fail(msg.str());
    }
    for (int k = 0; k < 3; ++k) {
      used[f[k]] = 1;
      const int a = f[k], b = f[(k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  for (int v = 0; v < n; ++v) {
    if (!used[v]) fail("vertex " + std::to_string(v) + " belongs to no triangle (it would have no mass)");
  }
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() > 2) {
      std::string list;
      for (int t : faces) list += (list.empty() ? "" : ", ") + std::to_string(t);
      fail("non-manifold edge (" + std::to_string(edge.first) + ", " + std::to_string(edge.second) +
           ") is shared by " + std::to_string(faces.size()) + " triangles (" + list + ")");
    }
  }
}

}  // namespace cloth_sim
