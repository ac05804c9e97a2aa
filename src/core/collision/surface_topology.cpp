#include "cloth_sim/core/collision/surface_topology.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace cloth_sim {

SurfaceTopology::SurfaceTopology(const Eigen::Matrix3Xi& triangles, int particles)
    : particles_(particles), triangles_(triangles) {
  const int n_tri = static_cast<int>(triangles.cols());
  // (min vertex, max vertex, triangle) for every triangle side, sorted: equal sides adjacent.
  std::vector<std::array<int, 3>> sides;
  sides.reserve(3 * n_tri);
  std::vector<int> vertex_owner(particles, -1);
  for (int t = 0; t < n_tri; ++t) {
    for (int a = 0; a < 3; ++a) {
      const int i = triangles(a, t), j = triangles((a + 1) % 3, t);
      if (i < 0 || i >= particles || j < 0 || j >= particles) {
        throw std::invalid_argument("self-contact: triangle " + std::to_string(t) +
                                    " has a vertex out of range");
      }
      if (i == j) {
        throw std::invalid_argument("self-contact: triangle " + std::to_string(t) +
                                    " repeats vertex " + std::to_string(i));
      }
      sides.push_back({std::min(i, j), std::max(i, j), t});
      if (vertex_owner[i] < 0) vertex_owner[i] = t;
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<int> edge_owner;
  for (std::size_t k = 0; k < sides.size();) {
    std::size_t m = k;
    std::array<int, 2> faces{-1, -1};
    int count = 0;
    while (m < sides.size() && sides[m][0] == sides[k][0] && sides[m][1] == sides[k][1]) {
      if (count < 2) faces[count] = sides[m][2];
      ++count;
      ++m;
    }
    edges_.push_back({sides[k][0], sides[k][1]});
    edge_faces_.push_back(faces);
    edge_owner.push_back(sides[k][2]);  // the lowest triangle: sides sorted by it last
    k = m;
  }
  // CSR lists of what each triangle owns.
  vertex_start_.assign(n_tri + 1, 0);
  edge_start_.assign(n_tri + 1, 0);
  for (int v = 0; v < particles; ++v) {
    if (vertex_owner[v] >= 0) ++vertex_start_[vertex_owner[v] + 1];
  }
  for (int owner : edge_owner) ++edge_start_[owner + 1];
  for (int t = 0; t < n_tri; ++t) {
    vertex_start_[t + 1] += vertex_start_[t];
    edge_start_[t + 1] += edge_start_[t];
  }
  owned_vertices_.resize(vertex_start_[n_tri]);
  owned_edges_.resize(edge_start_[n_tri]);
  std::vector<int> fill_v(vertex_start_.begin(), vertex_start_.end() - 1);
  std::vector<int> fill_e(edge_start_.begin(), edge_start_.end() - 1);
  for (int v = 0; v < particles; ++v) {
    if (vertex_owner[v] >= 0) owned_vertices_[fill_v[vertex_owner[v]]++] = v;
  }
  for (int e = 0; e < static_cast<int>(edge_owner.size()); ++e) {
    owned_edges_[fill_e[edge_owner[e]]++] = e;
  }
}

int SurfaceTopology::findEdge(int i, int j) const {
  const std::array<int, 2> key{std::min(i, j), std::max(i, j)};
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), key);  // edges_ are sorted
  return it != edges_.end() && *it == key ? static_cast<int>(it - edges_.begin()) : -1;
}

double SurfaceTopology::meanEdgeLength(const Points& rest) const {
  if (triangles_.cols() == 0) return 0.0;
  double sum = 0.0;
  for (Eigen::Index t = 0; t < triangles_.cols(); ++t) {
    for (int a = 0; a < 3; ++a) {
      sum += (rest.col(triangles_(a, t)) - rest.col(triangles_((a + 1) % 3, t))).norm();
    }
  }
  return sum / (3.0 * static_cast<double>(triangles_.cols()));
}

}  // namespace cloth_sim
