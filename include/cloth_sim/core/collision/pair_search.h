/// @file pair_search.h
/// Broad phase of triangle self-contact: the vertex-triangle and edge-edge pairs of one cloth
/// that may come within a reach of each other during a substep, from a bounding volume
/// hierarchy of its triangles with normal cones (docs/method.md, "Self-contact").
#pragma once

#include <array>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/collision/additive_ccd.h"
#include "cloth_sim/core/collision/surface_topology.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// A pair of primitives sharing no vertex: vertices (v[0]; v[1], v[2], v[3]) for a vertex and
/// a triangle, (v[0], v[1]; v[2], v[3]) for two edges.
struct PairCandidate {
  PairKind kind;
  std::array<int, 4> v;
};

/// Finds the candidate pairs of a substep.
///
/// A binary tree of the triangles is built once from the rest positions (each node splits its
/// triangles at the median of their centroids along its longest side), so each node is a
/// compact patch of the cloth. Each substep refits it: a node's box holds its triangles' paths
/// from start to end (straight lines), grown by reach / 2 on every side, and its normal box
/// holds their unit normals over the substep (the normal of a triangle moving linearly is
/// (1 - s)^2 A + 2 s (1 - s) B + s^2 C, s in [0, 1], a positive combination of the start normal
/// A, the end normal C and B = (e1(0) x e2(1) + e1(1) x e2(0)) / 2, so A, B and C bound it).
/// A node in one piece whose normals stay within 60 degrees of one direction is flat: it cannot
/// touch itself (Volino and Magnenat-Thalmann 1994, "Efficient self-collision detection on smoothly
/// discretized surface animations using geometrical shape regularity"; Provot 1997 for the
/// motion), so its pairs are skipped; the pairs of two nodes are tested only where their boxes
/// overlap. Each pair of overlapping triangles (A, B) gives the vertices A owns against B (and
/// B's against A) and the edges A owns against those B owns (SurfaceTopology), each pair of
/// primitives once, those sharing a vertex left out and each pair's own boxes tested.
///
/// Within a flat patch, pairs are neither contacts nor impacts: they stay apart by the cloth's
/// own extent, at least cos 60 deg times their distance along the cloth (the springs' business,
/// as pairs closer than the thickness at rest).
class PairSearch {
 public:
  /// Builds the tree of @p topology's triangles at @p rest (m).
  PairSearch(const SurfaceTopology& topology, const Points& rest);

  /// Fills @p out with the pairs of @p topology whose boxes overlap, the path of vertex i being
  /// @p start.col(i) to @p end.col(i) (m) and @p reach (m, >= 0) the distance of interest.
  void find(const SurfaceTopology& topology, const Points& start, const Points& end, double reach,
            std::vector<PairCandidate>& out);

  /// Triangle pairs whose boxes overlapped in the last find (for the benchmark).
  long trianglePairs() const { return triangle_pairs_; }

 private:
  struct Node {
    int left = -1, right = -1;  ///< children (both -1 for a leaf)
    int triangle = -1;          ///< a leaf's triangle
    bool connected = false;     ///< its triangles are one piece (vertex to vertex)
  };
  int build(const SurfaceTopology& topology, std::vector<int>& order, int begin, int end,
            const Points& centroids);
  void refit(const SurfaceTopology& topology, const Points& start, const Points& end);
  void self(int node);
  void pair(int a, int b);
  void pairTriangles(int a, int b);

  std::vector<Node> nodes_;  ///< preorder: a parent before its children
  std::vector<Eigen::AlignedBox3d> box_, normals_;
  std::vector<char> flat_, mark_;
  std::vector<Eigen::AlignedBox3d> vertex_box_, edge_box_;
  const SurfaceTopology* topology_ = nullptr;  ///< during find
  std::vector<PairCandidate>* out_ = nullptr;  ///< during find
  long triangle_pairs_ = 0;
};

}  // namespace cloth_sim
