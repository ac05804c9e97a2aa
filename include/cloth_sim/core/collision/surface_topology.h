/// @file surface_topology.h
/// The connectivity of a cloth's triangle mesh that triangle self-contact needs: its edges with
/// their faces, and which triangle "owns" each vertex and each edge, so that a search over
/// pairs of triangles lists every vertex-triangle and edge-edge pair exactly once (Bridson,
/// Fedkiw and Anderson 2002, "Robust treatment of collisions, contact and friction for cloth
/// animation", section 6.1, with the assignment of vertices and edges to triangles).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

class SurfaceTopology {
 public:
  /// @p triangles: vertex indices, one column per triangle, each in [0, @p particles).
  /// Throws std::invalid_argument for an index out of range or a triangle with a repeated
  /// vertex.
  SurfaceTopology(const Eigen::Matrix3Xi& triangles, int particles);

  int particleCount() const { return particles_; }
  int triangleCount() const { return static_cast<int>(triangles_.cols()); }
  int edgeCount() const { return static_cast<int>(edges_.size()); }
  const Eigen::Matrix3Xi& triangles() const { return triangles_; }
  /// Edge e's vertices (smaller index first).
  const std::array<int, 2>& edge(int e) const { return edges_[e]; }
  /// Edge e's faces: the one or two triangles that hold it (-1 for none).
  const std::array<int, 2>& edgeFaces(int e) const { return edge_faces_[e]; }
  /// The vertices and edges that triangle t owns (each vertex and edge has one owner: the
  /// lowest-numbered triangle holding it).
  const int* ownedVerticesBegin(int t) const { return owned_vertices_.data() + vertex_start_[t]; }
  const int* ownedVerticesEnd(int t) const { return owned_vertices_.data() + vertex_start_[t + 1]; }
  const int* ownedEdgesBegin(int t) const { return owned_edges_.data() + edge_start_[t]; }
  const int* ownedEdgesEnd(int t) const { return owned_edges_.data() + edge_start_[t + 1]; }
  /// The index of the edge between vertices @p i and @p j, or -1 when there is none.
  int findEdge(int i, int j) const;
  /// Whether triangle t holds vertex v.
  bool triangleHas(int t, int v) const {
    return triangles_(0, t) == v || triangles_(1, t) == v || triangles_(2, t) == v;
  }
  /// Mean length (m) of the triangles' sides at @p rest (an inner edge counts twice, as in
  /// each of its triangles): the automatic self-contact thickness.
  double meanEdgeLength(const Points& rest) const;

 private:
  int particles_ = 0;
  Eigen::Matrix3Xi triangles_;
  std::vector<std::array<int, 2>> edges_, edge_faces_;
  std::vector<int> vertex_start_, owned_vertices_, edge_start_, owned_edges_;
};

}  // namespace cloth_sim
