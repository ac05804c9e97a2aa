/// @file pair_search.h
/// Broad phase of triangle self-contact: the vertex-triangle and edge-edge pairs of one cloth
/// that may come within a reach of each other during a substep, from a bounding volume
/// hierarchy of its triangles with normal cones (docs/method.md, "Self-contact").
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
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
/// compact patch of the cloth (leaves of at most four triangles). Each substep refits it: a
/// triangle's box and an edge's hold their vertices' paths from start to end (straight lines)
/// grown by half the edge reach; a node's normal box holds its triangles' unit normals over the
/// substep (the normal of a triangle moving linearly is (1 - s)^2 A + 2 s (1 - s) B + s^2 C,
/// s in [0, 1], a positive combination of the start normal A, the end normal C and
/// B = (e1(0) x e2(1) + e1(1) x e2(0)) / 2, so A, B and C bound it). A leaf's normal box holds
/// those of its ring too, the triangles outside it that share a vertex with it: the leaf's own
/// triangles are joined at vertices, and a triangle folded over between two of them (outside
/// the leaf) lets them lie on top of each other with their own normals up (a tree leaf of two
/// triangles sharing a vertex let a particle through the other one unseen: the pin jump of the
/// untangling test at 32 x 32 ended crossed so). A node in one piece whose
/// normals stay within 60 degrees of one direction is flat: it cannot touch itself (Volino and
/// Magnenat-Thalmann 1994, "Efficient self-collision detection on smoothly discretized surface
/// animations using geometrical shape regularity"; Provot 1997 for the motion), so its pairs are
/// skipped; so are two flat nodes that share a vertex and whose normals together stay within
/// 60 degrees of one direction (flatTogether: one flat piece). The tree is walked against
/// itself, two nodes only where their boxes overlap: their triangles' boxes for the edges the
/// triangles own (SurfaceTopology: each edge pair once), the box of the vertices one node's
/// triangles own (each path grown by the rest of the vertex reach) against the other's
/// triangles for vertex-triangle pairs, pairs sharing a vertex left out. A vertex and a
/// triangle that come within the reach, or two edges within the edge reach, are listed.
///
/// Within a flat patch, pairs are neither contacts nor impacts: they stay apart by the cloth's
/// own extent, at least cos 60 deg times their distance along the cloth (the springs' business,
/// as pairs closer than the thickness at rest).
class PairSearch {
 public:
  /// Builds the tree of @p topology's triangles at @p rest (m).
  PairSearch(const SurfaceTopology& topology, const Points& rest);

  /// Fills @p out with the pairs of @p topology whose boxes overlap, the path of vertex i being
  /// @p start.col(i) to @p end.col(i) (m): vertex-triangle pairs that may come within @p reach
  /// (m, >= 0) of each other, edge-edge pairs within @p edge_reach (m, at most @p reach).
  /// @p cull_flat false: flat patches are searched too (for the pairs near each other at rest).
  void find(const SurfaceTopology& topology, const Points& start, const Points& end, double reach,
            double edge_reach, std::vector<PairCandidate>& out, bool cull_flat = true);

  /// Fills @p out with the pairs of @p topology held still at @p positions (m) whose boxes
  /// overlap for @p reach and @p edge_reach (m, as find) and that have a vertex marked in
  /// @p touched (one per vertex; nullptr: all): the pairs a PairList lists again for the vertices
  /// it anchors again. A PairList keeps its own PairSearch for this: with @p touched, only the
  /// boxes and normals of the marked vertices' triangles are refitted (the others are where
  /// the last call left them), and the walk enters only the nodes that hold a marked vertex.
  /// It skips the patches flat within 45 degrees whose triangles turn by at most 15 degrees
  /// while each vertex moves by at most @p margin (m): they stay flat within 60 degrees (the
  /// cone of find) over every motion the list covers.
  void findTouching(const SurfaceTopology& topology, const Points& positions, double reach,
                    double edge_reach, double margin, const std::vector<char>* touched,
                    std::vector<PairCandidate>& out);

  /// Threads of the tree walk (>= 1; its list is the same on any number).
  void setThreads(int threads) { threads_ = threads; }

  /// Triangle pairs whose boxes overlapped in the last find (for the benchmark).
  long trianglePairs() const { return triangle_pairs_; }
  /// Vertex-triangle pairs listed by the last find.
  long vertexPairs() const { return vertex_pairs_; }

 private:
  struct Node {
    int left = -1, right = -1;  ///< children (a leaf has none)
    int first = 0, last = 0;    ///< its triangles: order_[first, last)
    int count = 0;              ///< a leaf's number of triangles (0 for an inner node)
    bool connected = false;     ///< its triangles are one piece (vertex to vertex)
  };
  /// A box in single precision, rounded outwards (half the memory to walk).
  struct FloatBox {
    float lo[3], hi[3];
    static FloatBox outside(const Eigen::AlignedBox3d& box);
    FloatBox merged(const FloatBox& o) const {
      FloatBox m;
      for (int i = 0; i < 3; ++i) {
        m.lo[i] = lo[i] < o.lo[i] ? lo[i] : o.lo[i];
        m.hi[i] = hi[i] > o.hi[i] ? hi[i] : o.hi[i];
      }
      return m;
    }
    bool overlaps(const FloatBox& o) const {
      return lo[0] <= o.hi[0] && o.lo[0] <= hi[0] && lo[1] <= o.hi[1] && o.lo[1] <= hi[1] &&
             lo[2] <= o.hi[2] && o.lo[2] <= hi[2];
    }
  };
  int build(const SurfaceTopology& topology, int begin, int end, const Points& centroids);
  /// Whether a triangle of order_[a_begin, a_end) shares a vertex with one of [b_begin, b_end).
  /// @p mark: one zero per vertex (left so).
  bool sharesVertex(const SurfaceTopology& topology, int a_begin, int a_end, int b_begin,
                    int b_end, std::vector<char>& mark) const;
  /// dirty_triangle_ from dirty_: the triangles with a marked vertex.
  void markDirty(const SurfaceTopology& topology);
  /// Triangle @p t's normal box over the motion start -> end, and with a rotation margin
  /// whether it is strong_ (turns by at most 15 degrees).
  void triangleNormals(const SurfaceTopology& topology, const Points& start, const Points& end,
                       int t);
  /// Leaf @p k's normal box (its triangles' and its ring's), strength and flatness.
  void leafNormals(int k);
  /// Each triangle's normals over the motion start -> end, each node's normal box and flat_
  /// (no node is flat unless cull_flat_); with dirty_, only what the marked vertices change.
  void refitNormals(const SurfaceTopology& topology, const Points& start, const Points& end);
  /// The vertices', edges' and triangles' boxes of the motion grown by the reaches (as find),
  /// then each node's boxes; with dirty_, only what the marked vertices change.
  void refitBoxes(const SurfaceTopology& topology, const Points& start, const Points& end,
                  double reach, double edge_reach);
  /// body(i) for i in [0, @p count), in fixed blocks on threads_ (each i writes only its own).
  template <typename Body>
  void forEach(int count, Body&& body) const;
  /// Which pairs of two nodes are still to be found: edges of both, vertices of the first with
  /// triangles of the second, and the other way round.
  static constexpr unsigned kEdges = 1, kVerticesOfA = 2, kVerticesOfB = 4, kAll = 7;
  /// A piece of the walk: the pairs within node a, or those of @p tests between nodes a and b.
  struct Job {
    enum Kind { kSelf, kCross } kind;
    int a, b;
    unsigned tests;
  };
  /// What a job lists, and its scratch (a thread's own).
  struct Task {
    std::vector<PairCandidate> out;
    long triangle_pairs = 0, vertex_pairs = 0;
    std::vector<char> mark;  ///< one per vertex, for sharesVertex
    std::unordered_map<std::uint64_t, bool> learned;  ///< adjacencies to add to adjacent_
  };
  /// Whether the walk enters node @p k: always, unless findTouching marked vertices.
  bool live(int k) const { return dirty_ == nullptr || live_[k]; }
  /// The walk from the root into @p out: cut into jobs (split) run on threads_, joined in order.
  void walk(std::vector<PairCandidate>& out);
  /// Appends to @p next the jobs @p job recurses into (itself when it is a leaf or two).
  void split(const Job& job, std::vector<Job>& next);
  /// The pairs within node @p node (none when it is flat).
  void self(int node, Task& task);
  /// @p tests less those whose boxes do not meet between nodes @p a and @p b.
  unsigned remainingTests(int a, int b, unsigned tests) const;
  /// Whether cross descends into @p a (the larger; a leaf cannot be split) rather than @p b.
  bool descendsFirst(int a, int b) const;
  /// The pairs of @p tests between nodes @p a and @p b.
  void cross(int a, int b, unsigned tests, Task& task);
  /// Whether nodes @p a and @p b are flat (flat_) and together one flat piece: their normals
  /// within the flat cone of one direction, and sharing a vertex. Such a pair is skipped as a
  /// flat node is. @p task: where a running job keeps what it learns (nullptr: serial).
  bool flatTogether(int a, int b, Task* task);
  /// The pairs of @p tests between the triangles in slots @p i and @p j: the edges each owns,
  /// the vertices of one against the other.
  void leafPair(int i, int j, unsigned tests, Task& task) const;
  /// Vertex-triangle pairs of the vertices triangle @p owner owns with triangle @p other.
  void vertexTriangle(int owner, int other, Task& task) const;

  std::vector<Node> nodes_;  ///< preorder: a parent before its children
  std::vector<int> order_;   ///< the triangles, leaf by leaf
  /// The leaves, and the inner nodes children first (each after both its children).
  std::vector<int> leaves_, inner_;
  /// Each node's box (its triangles'), the box of the vertices its triangles own; each
  /// triangle's box and that of the vertices it owns (by order_ slot).
  std::vector<FloatBox> box_, vertex_nodes_, tight_box_, owned_box_;
  std::vector<int> slot_of_;     ///< each triangle's slot in order_
  std::vector<int> owner_slot_;  ///< the slot of each vertex's owner triangle (-1: none)
  std::vector<float> size_;               ///< each node box's largest side (m)
  std::vector<Eigen::AlignedBox3d> normals_;
  std::vector<char> flat_, mark_;
  /// CSR by node: a leaf's ring, the triangles outside it that share a vertex with it (empty for
  /// an inner node, whose normals are its leaves').
  std::vector<int> ring_start_, ring_;
  std::vector<Eigen::AlignedBox3d> triangle_normals_;  ///< each triangle's over the substep
  /// Whether two nodes share a vertex (key: the lower index times the node count plus the
  /// higher), filled as flatTogether asks.
  std::unordered_map<std::uint64_t, bool> adjacent_;
  /// Each vertex's path grown by half the edge reach, and by the rest of the reach; each edge's
  /// and each triangle's path grown by half the edge reach.
  std::vector<Eigen::AlignedBox3d> path_box_, vertex_box_, edge_box_, triangle_box_;
  const SurfaceTopology* topology_ = nullptr;  ///< during find
  int threads_ = 1;
  std::vector<Job> jobs_;
  std::vector<Task> tasks_;
  bool cull_flat_ = true;                      ///< during find
  /// During findTouching: the vertices whose boxes and normals are refitted (nullptr: all).
  const std::vector<char>* dirty_ = nullptr;
  std::vector<char> dirty_triangle_, dirty_node_;  ///< refitted in this stage
  double flat_cosine_ = 0.5;                    ///< the flat cone's cosine of this find
  double rotation_margin_ = 0.0;  ///< m: findTouching's margin (0: no strength required)
  /// Each triangle, and each node (its triangles and ring), turns by at most 15 degrees.
  std::vector<char> strong_, strong_node_;
  /// During findTouching: each node holds a triangle with a marked vertex (dirty_triangle_).
  std::vector<char> live_;
  long triangle_pairs_ = 0, vertex_pairs_ = 0;
};

}  // namespace cloth_sim
