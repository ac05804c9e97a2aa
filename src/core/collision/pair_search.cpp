#include "cloth_sim/core/collision/pair_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <cstdint>

namespace cloth_sim {
namespace {

/// cos 60 deg: a node is flat when every normal over the substep is within 60 degrees of its
/// normal box's centre direction.
constexpr double kFlatCosine = 0.5;
/// Triangles per leaf at most: the last levels of the tree cost more to walk than to test.
constexpr int kLeafSize = 4;

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

PairSearch::FloatBox PairSearch::FloatBox::outside(const Eigen::AlignedBox3d& box) {
  FloatBox f;
  if (box.isEmpty()) {  // overlaps nothing
    for (int i = 0; i < 3; ++i) {
      f.lo[i] = std::numeric_limits<float>::max();
      f.hi[i] = -std::numeric_limits<float>::max();
    }
    return f;
  }
  // A float is within 2^-24 of the double it rounds: moving each side out by 1e-7 of its size
  // first keeps the float box around the double one.
  for (int i = 0; i < 3; ++i) {
    const double lo = box.min()[i], hi = box.max()[i];
    f.lo[i] = static_cast<float>(lo - (std::abs(lo) * 1e-7 + 1e-30));
    f.hi[i] = static_cast<float>(hi + (std::abs(hi) * 1e-7 + 1e-30));
  }
  return f;
}

PairSearch::PairSearch(const SurfaceTopology& topology, const Points& rest) {
  const int n = topology.triangleCount();
  if (n == 0) return;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  Points centroids(3, n);
  for (int t = 0; t < n; ++t) {
    centroids.col(t) = (rest.col(tri(0, t)) + rest.col(tri(1, t)) + rest.col(tri(2, t))) / 3.0;
  }
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * n / kLeafSize + 2);
  mark_.assign(rest.cols(), 0);
  build(topology, 0, n, centroids);
  slot_of_.resize(n);
  for (int k = 0; k < n; ++k) slot_of_[order_[k]] = k;
  // Each leaf's ring: the triangles outside it that share a vertex with it.
  std::vector<std::vector<int>> around(rest.cols());
  for (int t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) around[tri(k, t)].push_back(t);
  }
  ring_start_.assign(nodes_.size() + 1, 0);
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const Node& node = nodes_[k];
    std::vector<int> ring;
    for (int j = node.first; j < node.first + node.count; ++j) {
      for (int a = 0; a < 3; ++a) {
        for (const int r : around[tri(a, order_[j])]) {
          if (slot_of_[r] < node.first || slot_of_[r] >= node.first + node.count) ring.push_back(r);
        }
      }
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    ring_.insert(ring_.end(), ring.begin(), ring.end());
    ring_start_[k + 1] = static_cast<int>(ring_.size());
  }
  owner_slot_.assign(rest.cols(), -1);
  for (int t = 0; t < n; ++t) {
    for (const int* v = topology.ownedVerticesBegin(t); v != topology.ownedVerticesEnd(t); ++v) {
      owner_slot_[*v] = slot_of_[t];
    }
  }
}

bool PairSearch::sharesVertex(const SurfaceTopology& topology, int a_begin, int a_end,
                              int b_begin, int b_end) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  for (int k = a_begin; k < a_end; ++k) {
    for (int i = 0; i < 3; ++i) mark_[tri(i, order_[k])] = 1;
  }
  bool shared = false;
  for (int k = b_begin; k < b_end && !shared; ++k) {
    for (int i = 0; i < 3; ++i) shared = shared || mark_[tri(i, order_[k])];
  }
  for (int k = a_begin; k < a_end; ++k) {
    for (int i = 0; i < 3; ++i) mark_[tri(i, order_[k])] = 0;
  }
  return shared;
}

int PairSearch::build(const SurfaceTopology& topology, int begin, int end, const Points& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  nodes_[index].first = begin;
  nodes_[index].last = end;
  if (end - begin <= kLeafSize) {
    Node& leaf = nodes_[index];
    leaf.count = end - begin;
    // One piece: grow a set from the first triangle by those sharing a vertex with it.
    int in = 1;
    for (int pass = 0; pass < kLeafSize && in < leaf.count; ++pass) {
      for (int k = begin + in; k < end; ++k) {
        if (sharesVertex(topology, begin, begin + in, k, k + 1)) {
          std::swap(order_[begin + in], order_[k]);
          ++in;
        }
      }
    }
    leaf.connected = in == leaf.count;
    return index;
  }
  Eigen::AlignedBox3d box;
  for (int k = begin; k < end; ++k) box.extend(Vec3(centroids.col(order_[k])));
  int axis = 0;
  box.sizes().maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) { return centroids(axis, a) < centroids(axis, b); });
  const int left = build(topology, begin, mid, centroids);
  const int right = build(topology, mid, end, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  // One piece when both halves are and they share a vertex (conservative: a half in two pieces
  // joined through the other half counts as two).
  nodes_[index].connected = nodes_[left].connected && nodes_[right].connected &&
                            sharesVertex(topology, begin, mid, mid, end);
  return index;
}

void PairSearch::refit(const SurfaceTopology& topology, const Points& start, const Points& end) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  box_.resize(nodes_.size());
  size_.resize(nodes_.size());
  normals_.resize(nodes_.size());
  flat_.resize(nodes_.size());
  tight_box_.resize(order_.size());
  vertex_nodes_.resize(nodes_.size());
  owned_box_.resize(order_.size());
  if (cull_flat_) {  // the normals serve only to skip flat patches
    triangle_normals_.resize(order_.size());
    for (int t = 0; t < static_cast<int>(order_.size()); ++t) {
      const int a = tri(0, t), b = tri(1, t), c = tri(2, t);
      const Vec3 e1s = start.col(b) - start.col(a), e2s = start.col(c) - start.col(a);
      const Vec3 e1e = end.col(b) - end.col(a), e2e = end.col(c) - end.col(a);
      Eigen::AlignedBox3d normals;
      extendUnit(normals, e1s.cross(e2s));
      extendUnit(normals, e1e.cross(e2e));
      extendUnit(normals, e1s.cross(e2e) + e1e.cross(e2s));
      triangle_normals_[t] = normals;
    }
  }
  for (int k = static_cast<int>(nodes_.size()) - 1; k >= 0; --k) {
    const Node& node = nodes_[k];
    Eigen::AlignedBox3d box, normals, vertices;
    if (node.count > 0) {
      for (int j = node.first; j < node.first + node.count; ++j) {
        const int t = order_[j];
        tight_box_[j] = FloatBox::outside(triangle_box_[t]);
        box.extend(triangle_box_[t]);
        Eigen::AlignedBox3d owned;
        for (const int* v = topology.ownedVerticesBegin(t); v != topology.ownedVerticesEnd(t);
             ++v) {
          owned.extend(vertex_box_[*v]);
        }
        owned_box_[j] = FloatBox::outside(owned);
        vertices.extend(owned);
        if (cull_flat_) normals.extend(triangle_normals_[t]);
      }
      // The leaf's ring too: a triangle folded over just outside the leaf lets two of its
      // triangles that share only a vertex lie on top of each other with their own normals up.
      if (cull_flat_) {
        for (int r = ring_start_[k]; r < ring_start_[k + 1]; ++r) {
          normals.extend(triangle_normals_[ring_[r]]);
        }
      }
    } else {
      box = Eigen::AlignedBox3d(Vec3(box_[node.left].lo[0], box_[node.left].lo[1], box_[node.left].lo[2]),
                                Vec3(box_[node.left].hi[0], box_[node.left].hi[1], box_[node.left].hi[2]));
      box.extend(Vec3(box_[node.right].lo[0], box_[node.right].lo[1], box_[node.right].lo[2]));
      box.extend(Vec3(box_[node.right].hi[0], box_[node.right].hi[1], box_[node.right].hi[2]));
      normals = normals_[node.left].merged(normals_[node.right]);
      vertex_nodes_[k] = vertex_nodes_[node.left].merged(vertex_nodes_[node.right]);
    }
    if (node.count > 0) vertex_nodes_[k] = FloatBox::outside(vertices);
    box_[k] = FloatBox::outside(box);
    size_[k] = static_cast<float>(box.sizes().maxCoeff());
    normals_[k] = normals;
    flat_[k] = node.connected && flat(normals);
  }
}

void PairSearch::find(const SurfaceTopology& topology, const Points& start, const Points& end,
                      double reach, double edge_reach, std::vector<PairCandidate>& out,
                      bool cull_flat) {
  cull_flat_ = cull_flat;
  out.clear();
  triangle_pairs_ = vertex_pairs_ = 0;
  if (nodes_.empty()) return;
  const int n_vertices = static_cast<int>(start.cols());
  // Triangles and edges grow by half the edge reach; a vertex by the rest of its reach, so that
  // its box meets a triangle's when their paths come within reach.
  const Vec3 edge_grow = Vec3::Constant(0.5 * edge_reach);
  const Vec3 grow = Vec3::Constant(reach - 0.5 * edge_reach);
  vertex_box_.resize(n_vertices);
  path_box_.resize(n_vertices);
  for (int i = 0; i < n_vertices; ++i) {
    const Vec3 a = start.col(i), b = end.col(i);
    path_box_[i] = Eigen::AlignedBox3d(a.cwiseMin(b) - edge_grow, a.cwiseMax(b) + edge_grow);
    vertex_box_[i] = Eigen::AlignedBox3d(a.cwiseMin(b) - grow, a.cwiseMax(b) + grow);
  }
  edge_box_.resize(topology.edgeCount());
  for (int e = 0; e < topology.edgeCount(); ++e) {
    const auto& v = topology.edge(e);
    edge_box_[e] = path_box_[v[0]].merged(path_box_[v[1]]);
  }
  const Eigen::Matrix3Xi& tri = topology.triangles();
  triangle_box_.resize(topology.triangleCount());
  for (int t = 0; t < topology.triangleCount(); ++t) {
    triangle_box_[t] =
        path_box_[tri(0, t)].merged(path_box_[tri(1, t)]).merged(path_box_[tri(2, t)]);
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
  if (cull_flat_ && flat_[node]) return;
  if (n.count > 0) {
    for (int i = n.first; i < n.first + n.count; ++i) {
      for (int j = i + 1; j < n.first + n.count; ++j) leafPair(i, j, kAll);
    }
    return;
  }
  self(n.left);
  self(n.right);
  cross(n.left, n.right, kAll);
}

void PairSearch::cross(int a, int b, unsigned tests) {
  // Drop the tests whose boxes no longer meet: they cannot meet below either.
  if ((tests & kEdges) && !box_[a].overlaps(box_[b])) tests &= ~kEdges;
  if ((tests & kVerticesOfA) && !vertex_nodes_[a].overlaps(box_[b])) tests &= ~kVerticesOfA;
  if ((tests & kVerticesOfB) && !vertex_nodes_[b].overlaps(box_[a])) tests &= ~kVerticesOfB;
  if (tests == 0) return;
  if (cull_flat_ && flatTogether(a, b)) return;
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (na.count > 0 && nb.count > 0) {
    for (int i = na.first; i < na.first + na.count; ++i) {
      for (int j = nb.first; j < nb.first + nb.count; ++j) leafPair(i, j, tests);
    }
    return;
  }
  // Descend the larger node (a leaf cannot be split).
  if (nb.count > 0 || (na.count == 0 && size_[a] >= size_[b])) {
    cross(na.left, b, tests);
    cross(na.right, b, tests);
  } else {
    cross(a, nb.left, tests);
    cross(a, nb.right, tests);
  }
}

bool PairSearch::flatTogether(int a, int b) {
  if (!flat_[a] || !flat_[b] || !flat(normals_[a].merged(normals_[b]))) return false;
  // One piece when each is and they share a vertex: asked once per pair of nodes (the mesh does
  // not change), and only of pairs whose normals would let them be skipped.
  const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) * nodes_.size() +
                            static_cast<std::uint64_t>(std::max(a, b));
  const auto known = adjacent_.find(key);
  if (known != adjacent_.end()) return known->second;
  const Node &na = nodes_[a], &nb = nodes_[b];
  const bool adjacent = sharesVertex(*topology_, na.first, na.last, nb.first, nb.last);
  adjacent_.emplace(key, adjacent);
  return adjacent;
}

void PairSearch::leafPair(int i, int j, unsigned tests) {
  const SurfaceTopology& topology = *topology_;
  const int a = order_[i], b = order_[j];
  if ((tests & kEdges) && tight_box_[i].overlaps(tight_box_[j])) {
    ++triangle_pairs_;
    for (const int* e = topology.ownedEdgesBegin(a); e != topology.ownedEdgesEnd(a); ++e) {
      const auto& ea = topology.edge(*e);
      for (const int* f = topology.ownedEdgesBegin(b); f != topology.ownedEdgesEnd(b); ++f) {
        const auto& eb = topology.edge(*f);
        if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
        if (!edge_box_[*e].intersects(edge_box_[*f])) continue;
        out_->push_back({PairKind::kEdgeEdge, {ea[0], ea[1], eb[0], eb[1]}});
      }
    }
  }
  if ((tests & kVerticesOfA) && owned_box_[i].overlaps(tight_box_[j])) vertexTriangle(a, b);
  if ((tests & kVerticesOfB) && owned_box_[j].overlaps(tight_box_[i])) vertexTriangle(b, a);
}

void PairSearch::vertexTriangle(int owner, int other) {
  const SurfaceTopology& topology = *topology_;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const Eigen::AlignedBox3d& other_box = triangle_box_[other];
  for (const int* v = topology.ownedVerticesBegin(owner); v != topology.ownedVerticesEnd(owner);
       ++v) {
    if (topology.triangleHas(other, *v) || !vertex_box_[*v].intersects(other_box)) continue;
    ++vertex_pairs_;
    out_->push_back({PairKind::kVertexTriangle, {*v, tri(0, other), tri(1, other), tri(2, other)}});
  }
}

}  // namespace cloth_sim
