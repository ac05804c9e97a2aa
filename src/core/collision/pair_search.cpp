#include "cloth_sim/core/collision/pair_search.h"

#include <algorithm>
#include <numeric>

namespace cloth_sim {
namespace {

/// cos 60 deg: a node is flat when every normal over the substep is within 60 degrees of its
/// normal box's centre direction.
constexpr double kFlatCosine = 0.5;

/// Adds unit(@p n) to @p box (a zero vector adds nothing).
void extendUnit(Eigen::AlignedBox3d& box, const Vec3& n) {
  const double length = n.norm();
  if (length > 0.0) box.extend(Vec3(n / length));
}

/// Whether every unit vector in @p normals lies within acos(kFlatCosine) of its centre's
/// direction: for n in the box [c - h, c + h], n . c >= c . c - sum_i |c_i| h_i.
bool flat(const Eigen::AlignedBox3d& normals) {
  if (normals.isEmpty()) return false;
  const Vec3 c = normals.center(), h = 0.5 * normals.sizes();
  const double length = c.norm();
  if (!(length > 0.0)) return false;
  return c.squaredNorm() - c.cwiseAbs().dot(h) >= kFlatCosine * length;
}

}  // namespace

PairSearch::PairSearch(const SurfaceTopology& topology, const Points& rest) {
  const int n = topology.triangleCount();
  if (n == 0) return;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  Points centroids(3, n);
  for (int t = 0; t < n; ++t) {
    centroids.col(t) = (rest.col(tri(0, t)) + rest.col(tri(1, t)) + rest.col(tri(2, t))) / 3.0;
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(2 * n);
  mark_.assign(rest.cols(), 0);
  build(topology, order, 0, n, centroids);
  mark_.clear();
}

int PairSearch::build(const SurfaceTopology& topology, std::vector<int>& order, int begin,
                      int end, const Points& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin == 1) {
    nodes_[index].triangle = order[begin];
    nodes_[index].connected = true;
    return index;
  }
  Eigen::AlignedBox3d box;
  for (int k = begin; k < end; ++k) box.extend(Vec3(centroids.col(order[k])));
  int axis = 0;
  box.sizes().maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](int a, int b) { return centroids(axis, a) < centroids(axis, b); });
  const int left = build(topology, order, begin, mid, centroids);
  const int right = build(topology, order, mid, end, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  // One piece when both halves are and they share a vertex (conservative: a half in two pieces
  // joined through the other half counts as two).
  bool shared = false;
  if (nodes_[left].connected && nodes_[right].connected) {
    const Eigen::Matrix3Xi& tri = topology.triangles();
    for (int k = begin; k < mid; ++k) {
      for (int a = 0; a < 3; ++a) mark_[tri(a, order[k])] = 1;
    }
    for (int k = mid; k < end && !shared; ++k) {
      for (int a = 0; a < 3; ++a) shared = shared || mark_[tri(a, order[k])];
    }
    for (int k = begin; k < mid; ++k) {
      for (int a = 0; a < 3; ++a) mark_[tri(a, order[k])] = 0;
    }
  }
  nodes_[index].connected = shared;
  return index;
}

void PairSearch::refit(const SurfaceTopology& topology, const Points& start, const Points& end) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  box_.resize(nodes_.size());
  normals_.resize(nodes_.size());
  flat_.resize(nodes_.size());
  for (int k = static_cast<int>(nodes_.size()) - 1; k >= 0; --k) {
    const Node& node = nodes_[k];
    if (node.triangle >= 0) {
      const int t = node.triangle, a = tri(0, t), b = tri(1, t), c = tri(2, t);
      box_[k] = vertex_box_[a].merged(vertex_box_[b]).merged(vertex_box_[c]);
      const Vec3 e1s = start.col(b) - start.col(a), e2s = start.col(c) - start.col(a);
      const Vec3 e1e = end.col(b) - end.col(a), e2e = end.col(c) - end.col(a);
      Eigen::AlignedBox3d normals;
      extendUnit(normals, e1s.cross(e2s));
      extendUnit(normals, e1e.cross(e2e));
      extendUnit(normals, e1s.cross(e2e) + e1e.cross(e2s));
      normals_[k] = normals;
      flat_[k] = 1;  // a single triangle has no pair of its own
    } else {
      box_[k] = box_[node.left].merged(box_[node.right]);
      normals_[k] = normals_[node.left].merged(normals_[node.right]);
      flat_[k] = node.connected && flat(normals_[k]);
    }
  }
}

void PairSearch::find(const SurfaceTopology& topology, const Points& start, const Points& end,
                      double reach, std::vector<PairCandidate>& out) {
  out.clear();
  triangle_pairs_ = 0;
  if (nodes_.empty()) return;
  const int n_vertices = static_cast<int>(start.cols());
  const Vec3 grow = Vec3::Constant(0.5 * reach);
  vertex_box_.resize(n_vertices);
  for (int i = 0; i < n_vertices; ++i) {
    const Vec3 a = start.col(i), b = end.col(i);
    vertex_box_[i] = Eigen::AlignedBox3d(a.cwiseMin(b) - grow, a.cwiseMax(b) + grow);
  }
  edge_box_.resize(topology.edgeCount());
  for (int e = 0; e < topology.edgeCount(); ++e) {
    const auto& v = topology.edge(e);
    edge_box_[e] = vertex_box_[v[0]].merged(vertex_box_[v[1]]);
  }
  refit(topology, start, end);
  topology_ = &topology;
  out_ = &out;
  self(0);
  topology_ = nullptr;
  out_ = nullptr;
}

void PairSearch::self(int node) {
  const Node& n = nodes_[node];
  if (n.triangle >= 0 || flat_[node]) return;
  self(n.left);
  self(n.right);
  pair(n.left, n.right);
}

void PairSearch::pair(int a, int b) {
  if (!box_[a].intersects(box_[b])) return;
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (na.triangle >= 0 && nb.triangle >= 0) {
    pairTriangles(na.triangle, nb.triangle);
    return;
  }
  // Descend the larger node (a leaf cannot be split).
  const bool split_a =
      nb.triangle >= 0 || (na.triangle < 0 && box_[a].sizes().maxCoeff() >= box_[b].sizes().maxCoeff());
  if (split_a) {
    pair(na.left, b);
    pair(na.right, b);
  } else {
    pair(a, nb.left);
    pair(a, nb.right);
  }
}

void PairSearch::pairTriangles(int a, int b) {
  ++triangle_pairs_;
  const SurfaceTopology& topology = *topology_;
  std::vector<PairCandidate>& out = *out_;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const auto triangle_box = [&](int t) {
    return vertex_box_[tri(0, t)].merged(vertex_box_[tri(1, t)]).merged(vertex_box_[tri(2, t)]);
  };
  for (int side = 0; side < 2; ++side) {
    const int owner = side == 0 ? a : b, other = side == 0 ? b : a;
    const int* v = topology.ownedVerticesBegin(owner);
    const int* v_end = topology.ownedVerticesEnd(owner);
    if (v == v_end) continue;
    const Eigen::AlignedBox3d other_box = triangle_box(other);
    for (; v != v_end; ++v) {
      if (topology.triangleHas(other, *v) || !vertex_box_[*v].intersects(other_box)) continue;
      out.push_back({PairKind::kVertexTriangle, {*v, tri(0, other), tri(1, other), tri(2, other)}});
    }
  }
  for (const int* e = topology.ownedEdgesBegin(a); e != topology.ownedEdgesEnd(a); ++e) {
    const auto& ea = topology.edge(*e);
    for (const int* f = topology.ownedEdgesBegin(b); f != topology.ownedEdgesEnd(b); ++f) {
      const auto& eb = topology.edge(*f);
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      if (!edge_box_[*e].intersects(edge_box_[*f])) continue;
      out.push_back({PairKind::kEdgeEdge, {ea[0], ea[1], eb[0], eb[1]}});
    }
  }
}

}  // namespace cloth_sim
