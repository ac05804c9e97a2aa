#include "cloth_sim/core/collision/pair_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <cstdint>

#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim {
namespace {

/// cos 60 deg: a node is flat when every normal over the substep is within 60 degrees of its
/// normal box's centre direction.
constexpr double kFlatCosine = 0.5;
/// cos 45 deg: findTouching skips only patches flat within 45 degrees whose triangles turn by at
/// most 15 degrees (sin 15 deg) while their vertices stay within its margin: within 60 degrees,
/// such a patch stays flat over any motion the list it serves covers.
constexpr double kTouchingFlatCosine = 0.70710678118654752;
constexpr double kTurnSine = 0.25881904510252076;
/// Triangles per leaf at most: the last levels of the tree cost more to walk than to test.
constexpr int kLeafSize = 4;
/// With threads, the walk is cut into about this many jobs (at most kSplitLevels levels from
/// the root), so that two threads finish together although the tasks' work differs.
constexpr int kJobs = 64;
constexpr int kSplitLevels = 12;
/// Items (vertices, edges, triangles, leaves) per block of the refit's loops.
constexpr std::size_t kGrain = 1024;

/// Adds unit(@p n) to @p box (a zero vector adds nothing).
void extendUnit(Eigen::AlignedBox3d& box, const Vec3& n) {
  const double length = n.norm();
  if (length > 0.0) box.extend(Vec3(n / length));
}

/// Whether every unit vector in @p normals lies within acos(@p cosine) of its centre's
/// direction: for n in the box [c - h, c + h], n . c >= c . c - sum_i |c_i| h_i.
bool flat(const Eigen::AlignedBox3d& normals, double cosine = kFlatCosine) {
  if (normals.isEmpty()) return false;
  const Vec3 c = normals.center(), h = 0.5 * normals.sizes();
  const double length = c.norm();
  if (!(length > 0.0)) return false;
  return c.squaredNorm() - c.cwiseAbs().dot(h) >= cosine * length;
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
  for (int k = static_cast<int>(nodes_.size()) - 1; k >= 0; --k) {
    (nodes_[k].count > 0 ? leaves_ : inner_).push_back(k);
  }
  owner_slot_.assign(rest.cols(), -1);
  for (int t = 0; t < n; ++t) {
    for (const int* v = topology.ownedVerticesBegin(t); v != topology.ownedVerticesEnd(t); ++v) {
      owner_slot_[*v] = slot_of_[t];
    }
  }
}

bool PairSearch::sharesVertex(const SurfaceTopology& topology, int a_begin, int a_end,
                              int b_begin, int b_end, std::vector<char>& mark) const {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  for (int k = a_begin; k < a_end; ++k) {
    for (int i = 0; i < 3; ++i) mark[tri(i, order_[k])] = 1;
  }
  bool shared = false;
  for (int k = b_begin; k < b_end && !shared; ++k) {
    for (int i = 0; i < 3; ++i) shared = shared || mark[tri(i, order_[k])];
  }
  for (int k = a_begin; k < a_end; ++k) {
    for (int i = 0; i < 3; ++i) mark[tri(i, order_[k])] = 0;
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
        if (sharesVertex(topology, begin, begin + in, k, k + 1, mark_)) {
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
                            sharesVertex(topology, begin, mid, mid, end, mark_);
  return index;
}

template <typename Body>
void PairSearch::forEach(int count, Body&& body) const {
  const BlockSplit split(static_cast<std::size_t>(count), kGrain);
  parallelFor(threads_, split.blocks(), [&](int block) {
    for (std::size_t i = split.begin(block); i < split.end(block); ++i) body(static_cast<int>(i));
  });
}

void PairSearch::markDirty(const SurfaceTopology& topology) {
  if (dirty_ == nullptr) return;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const std::vector<char>& mark = *dirty_;
  dirty_triangle_.resize(order_.size());
  for (int t = 0; t < static_cast<int>(order_.size()); ++t) {
    dirty_triangle_[t] = mark[tri(0, t)] || mark[tri(1, t)] || mark[tri(2, t)];
  }
  // The walk enters the nodes holding a marked triangle.
  live_.assign(nodes_.size(), 0);
  for (const int k : leaves_) {
    const Node& node = nodes_[k];
    for (int j = node.first; j < node.first + node.count; ++j) {
      live_[k] = live_[k] || dirty_triangle_[order_[j]];
    }
  }
  for (const int k : inner_) live_[k] = live_[nodes_[k].left] || live_[nodes_[k].right];
}

void PairSearch::triangleNormals(const SurfaceTopology& topology, const Points& start,
                                 const Points& end, int t) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const int a = tri(0, t), b = tri(1, t), c = tri(2, t);
  const Vec3 e1s = start.col(b) - start.col(a), e2s = start.col(c) - start.col(a);
  const Vec3 e1e = end.col(b) - end.col(a), e2e = end.col(c) - end.col(a);
  Eigen::AlignedBox3d normals;
  extendUnit(normals, e1s.cross(e2s));
  extendUnit(normals, e1e.cross(e2e));
  extendUnit(normals, e1s.cross(e2e) + e1e.cross(e2s));
  triangle_normals_[t] = normals;
  if (rotation_margin_ > 0.0) {
    // Moving each vertex by at most m changes e1 x e2 by at most 2 m (|e1| + |e2|) + 4 m^2, so
    // the normal turns by at most the asin of that over |e1 x e2| (e1, e2 from the vertex
    // between the two shortest edges).
    const Vec3 e3s = start.col(c) - start.col(b);
    const double l1 = e1s.norm(), l2 = e2s.norm(), l3 = e3s.norm();
    const double shortest_two = l1 + l2 + l3 - std::max(l1, std::max(l2, l3));
    const double m = rotation_margin_;
    const double change = 2.0 * m * shortest_two + 4.0 * m * m;
    strong_[t] = change <= kTurnSine * e1s.cross(e2s).norm();
  }
}

void PairSearch::leafNormals(int k) {
  const Node& node = nodes_[k];
  Eigen::AlignedBox3d normals;
  bool strong = true;
  const auto add = [&](int t) {
    normals.extend(triangle_normals_[t]);
    strong = strong && (rotation_margin_ == 0.0 || strong_[t]);
  };
  for (int j = node.first; j < node.first + node.count; ++j) add(order_[j]);
  // The leaf's ring too: a triangle folded over just outside the leaf lets two of its
  // triangles that share only a vertex lie on top of each other with their own normals up.
  for (int r = ring_start_[k]; r < ring_start_[k + 1]; ++r) add(ring_[r]);
  normals_[k] = normals;
  strong_node_[k] = strong;
  flat_[k] = node.connected && strong && flat(normals, flat_cosine_);
}

void PairSearch::refitNormals(const SurfaceTopology& topology, const Points& start,
                              const Points& end) {
  const bool fresh = normals_.size() != nodes_.size() || dirty_ == nullptr;
  normals_.resize(nodes_.size());
  flat_.resize(nodes_.size());
  strong_node_.resize(nodes_.size());
  if (!cull_flat_) {  // the normals serve only to skip flat patches
    std::fill(flat_.begin(), flat_.end(), 0);
    return;
  }
  triangle_normals_.resize(order_.size());
  strong_.resize(order_.size());
  forEach(static_cast<int>(order_.size()), [&](int t) {
    if (fresh || dirty_triangle_[t]) triangleNormals(topology, start, end, t);
  });
  dirty_node_.assign(nodes_.size(), fresh);
  if (!fresh) {  // a leaf whose triangles or ring changed
    for (const int k : leaves_) {
      const Node& node = nodes_[k];
      bool dirty = false;
      for (int j = node.first; j < node.first + node.count && !dirty; ++j) {
        dirty = dirty_triangle_[order_[j]];
      }
      for (int r = ring_start_[k]; r < ring_start_[k + 1] && !dirty; ++r) {
        dirty = dirty_triangle_[ring_[r]];
      }
      dirty_node_[k] = dirty;
    }
  }
  forEach(static_cast<int>(leaves_.size()), [&](int l) {
    if (dirty_node_[leaves_[l]]) leafNormals(leaves_[l]);
  });
  for (const int k : inner_) {  // children first
    const Node& node = nodes_[k];
    if (!dirty_node_[node.left] && !dirty_node_[node.right]) continue;
    dirty_node_[k] = 1;
    normals_[k] = normals_[node.left].merged(normals_[node.right]);
    strong_node_[k] = strong_node_[node.left] && strong_node_[node.right];
    flat_[k] = node.connected && strong_node_[k] && flat(normals_[k], flat_cosine_);
  }
}

void PairSearch::refitBoxes(const SurfaceTopology& topology, const Points& start,
                            const Points& end, double reach, double edge_reach) {
  const bool fresh = box_.size() != nodes_.size() || dirty_ == nullptr;
  const int n_vertices = static_cast<int>(start.cols());
  // Triangles and edges grow by half the edge reach; a vertex by the rest of its reach, so that
  // its box meets a triangle's when their paths come within reach.
  const Vec3 edge_grow = Vec3::Constant(0.5 * edge_reach);
  const Vec3 grow = Vec3::Constant(reach - 0.5 * edge_reach);
  vertex_box_.resize(n_vertices);
  path_box_.resize(n_vertices);
  forEach(n_vertices, [&](int i) {
    if (!fresh && !(*dirty_)[i]) return;
    const Vec3 a = start.col(i), b = end.col(i);
    path_box_[i] = Eigen::AlignedBox3d(a.cwiseMin(b) - edge_grow, a.cwiseMax(b) + edge_grow);
    vertex_box_[i] = Eigen::AlignedBox3d(a.cwiseMin(b) - grow, a.cwiseMax(b) + grow);
  });
  edge_box_.resize(topology.edgeCount());
  forEach(topology.edgeCount(), [&](int e) {
    const auto& v = topology.edge(e);
    if (fresh || (*dirty_)[v[0]] || (*dirty_)[v[1]]) {
      edge_box_[e] = path_box_[v[0]].merged(path_box_[v[1]]);
    }
  });
  const Eigen::Matrix3Xi& tri = topology.triangles();
  triangle_box_.resize(topology.triangleCount());
  forEach(topology.triangleCount(), [&](int t) {
    if (fresh || dirty_triangle_[t]) {
      triangle_box_[t] =
          path_box_[tri(0, t)].merged(path_box_[tri(1, t)]).merged(path_box_[tri(2, t)]);
    }
  });
  box_.resize(nodes_.size());
  size_.resize(nodes_.size());
  tight_box_.resize(order_.size());
  vertex_nodes_.resize(nodes_.size());
  owned_box_.resize(order_.size());
  const auto set = [&](int k, const Eigen::AlignedBox3d& box) {
    box_[k] = FloatBox::outside(box);
    size_[k] = static_cast<float>(box.sizes().maxCoeff());
  };
  // Not fresh, only the nodes holding a marked triangle change: the live ones (markDirty).
  forEach(static_cast<int>(leaves_.size()), [&](int l) {
    const int k = leaves_[l];
    const Node& node = nodes_[k];
    if (!fresh && !live_[k]) return;
    Eigen::AlignedBox3d box, vertices;
    for (int j = node.first; j < node.first + node.count; ++j) {
      const int t = order_[j];
      tight_box_[j] = FloatBox::outside(triangle_box_[t]);
      box.extend(triangle_box_[t]);
      Eigen::AlignedBox3d owned;
      for (const int* v = topology.ownedVerticesBegin(t); v != topology.ownedVerticesEnd(t); ++v) {
        owned.extend(vertex_box_[*v]);
      }
      owned_box_[j] = FloatBox::outside(owned);
      vertices.extend(owned);
    }
    vertex_nodes_[k] = FloatBox::outside(vertices);
    set(k, box);
  });
  for (const int k : inner_) {
    const Node& node = nodes_[k];
    if (!fresh && !live_[k]) continue;
    const FloatBox &left = box_[node.left], &right = box_[node.right];
    Eigen::AlignedBox3d box(Vec3(left.lo[0], left.lo[1], left.lo[2]),
                            Vec3(left.hi[0], left.hi[1], left.hi[2]));
    box.extend(Vec3(right.lo[0], right.lo[1], right.lo[2]));
    box.extend(Vec3(right.hi[0], right.hi[1], right.hi[2]));
    vertex_nodes_[k] = vertex_nodes_[node.left].merged(vertex_nodes_[node.right]);
    set(k, box);
  }
}

void PairSearch::find(const SurfaceTopology& topology, const Points& start, const Points& end,
                      double reach, double edge_reach, std::vector<PairCandidate>& out,
                      bool cull_flat) {
  cull_flat_ = cull_flat;
  out.clear();
  triangle_pairs_ = vertex_pairs_ = 0;
  if (nodes_.empty()) return;
  markDirty(topology);
  refitNormals(topology, start, end);
  if (cull_flat_ && flat_[0]) {  // one flat piece: no pair, so no box is needed
    box_.clear();                // (and the boxes are now stale)
    return;
  }
  refitBoxes(topology, start, end, reach, edge_reach);
  topology_ = &topology;
  walk(out);
  topology_ = nullptr;
}

void PairSearch::findTouching(const SurfaceTopology& topology, const Points& positions,
                              double reach, double edge_reach, double margin,
                              const std::vector<char>* touched, std::vector<PairCandidate>& out) {
  dirty_ = touched;
  flat_cosine_ = kTouchingFlatCosine;
  rotation_margin_ = margin;
  find(topology, positions, positions, reach, edge_reach, out);
  rotation_margin_ = 0.0;
  flat_cosine_ = kFlatCosine;
  dirty_ = nullptr;
  if (touched == nullptr) return;
  // A live leaf's unmarked triangles list pairs of unmarked vertices too.
  const std::vector<char>& mark = *touched;
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](const PairCandidate& p) {
                             return !(mark[p.v[0]] || mark[p.v[1]] || mark[p.v[2]] ||
                                      mark[p.v[3]]);
                           }),
            out.end());
}

void PairSearch::walk(std::vector<PairCandidate>& out) {
  // The recursion from the root, cut into jobs in the order it would visit them: each job lists
  // the pairs the recursion lists at its place, so joining the jobs' lists in order gives the
  // serial list, on any number of threads.
  jobs_.assign(1, Job{Job::kSelf, 0, 0, kAll});
  if (threads_ > 1) {
    std::vector<Job> next;
    for (int level = 0; level < kSplitLevels && static_cast<int>(jobs_.size()) < kJobs; ++level) {
      next.clear();
      for (const Job& job : jobs_) split(job, next);
      jobs_.swap(next);
    }
  }
  const int count = static_cast<int>(jobs_.size());
  if (static_cast<int>(tasks_.size()) < count) tasks_.resize(count);
  for (int k = 0; k < count; ++k) {
    Task& task = tasks_[k];
    task.out.clear();
    task.learned.clear();
    task.triangle_pairs = task.vertex_pairs = 0;
    if (task.mark.size() != mark_.size()) task.mark.assign(mark_.size(), 0);
  }
  parallelFor(threads_, count, [&](int k) {
    const Job& job = jobs_[k];
    if (job.kind == Job::kSelf) {
      self(job.a, tasks_[k]);
    } else {
      cross(job.a, job.b, job.tests, tasks_[k]);
    }
  }, 2);
  std::size_t total = 0;
  for (int k = 0; k < count; ++k) total += tasks_[k].out.size();
  out.reserve(total);
  for (int k = 0; k < count; ++k) {
    const Task& task = tasks_[k];
    out.insert(out.end(), task.out.begin(), task.out.end());
    triangle_pairs_ += task.triangle_pairs;
    vertex_pairs_ += task.vertex_pairs;
    adjacent_.insert(task.learned.begin(), task.learned.end());
  }
}

void PairSearch::split(const Job& job, std::vector<Job>& next) {
  // One level of self or cross as they recurse: what they skip is dropped, a leaf or a pair of
  // leaves stays one job.
  if (job.kind == Job::kSelf) {
    const Node& n = nodes_[job.a];
    if (!live(job.a) || (cull_flat_ && flat_[job.a])) return;
    if (n.count > 0) {
      next.push_back(job);
      return;
    }
    next.push_back({Job::kSelf, n.left, 0, kAll});
    next.push_back({Job::kSelf, n.right, 0, kAll});
    next.push_back({Job::kCross, n.left, n.right, kAll});
    return;
  }
  const int a = job.a, b = job.b;
  if (!live(a) && !live(b)) return;
  const unsigned tests = remainingTests(a, b, job.tests);
  if (tests == 0) return;
  if (cull_flat_ && flatTogether(a, b, nullptr)) return;
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (na.count > 0 && nb.count > 0) {
    next.push_back({Job::kCross, a, b, tests});
  } else if (descendsFirst(a, b)) {
    next.push_back({Job::kCross, na.left, b, tests});
    next.push_back({Job::kCross, na.right, b, tests});
  } else {
    next.push_back({Job::kCross, a, nb.left, tests});
    next.push_back({Job::kCross, a, nb.right, tests});
  }
}

void PairSearch::self(int node, Task& task) {
  const Node& n = nodes_[node];
  if (!live(node) || (cull_flat_ && flat_[node])) return;
  if (n.count > 0) {
    for (int i = n.first; i < n.first + n.count; ++i) {
      for (int j = i + 1; j < n.first + n.count; ++j) leafPair(i, j, kAll, task);
    }
    return;
  }
  self(n.left, task);
  self(n.right, task);
  cross(n.left, n.right, kAll, task);
}

unsigned PairSearch::remainingTests(int a, int b, unsigned tests) const {
  // Drop the tests whose boxes no longer meet: they cannot meet below either.
  if ((tests & kEdges) && !box_[a].overlaps(box_[b])) tests &= ~kEdges;
  if ((tests & kVerticesOfA) && !vertex_nodes_[a].overlaps(box_[b])) tests &= ~kVerticesOfA;
  if ((tests & kVerticesOfB) && !vertex_nodes_[b].overlaps(box_[a])) tests &= ~kVerticesOfB;
  return tests;
}

bool PairSearch::descendsFirst(int a, int b) const {
  // The larger node (a leaf cannot be split).
  const Node &na = nodes_[a], &nb = nodes_[b];
  return nb.count > 0 || (na.count == 0 && size_[a] >= size_[b]);
}

void PairSearch::cross(int a, int b, unsigned tests, Task& task) {
  if (!live(a) && !live(b)) return;
  tests = remainingTests(a, b, tests);
  if (tests == 0) return;
  if (cull_flat_ && flatTogether(a, b, &task)) return;
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (na.count > 0 && nb.count > 0) {
    for (int i = na.first; i < na.first + na.count; ++i) {
      for (int j = nb.first; j < nb.first + nb.count; ++j) leafPair(i, j, tests, task);
    }
    return;
  }
  if (descendsFirst(a, b)) {
    cross(na.left, b, tests, task);
    cross(na.right, b, tests, task);
  } else {
    cross(a, nb.left, tests, task);
    cross(a, nb.right, tests, task);
  }
}

bool PairSearch::flatTogether(int a, int b, Task* task) {
  if (!flat_[a] || !flat_[b] || !flat(normals_[a].merged(normals_[b]), flat_cosine_)) return false;
  // One piece when each is and they share a vertex: asked once per pair of nodes (the mesh does
  // not change), and only of pairs whose normals would let them be skipped.
  const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) * nodes_.size() +
                            static_cast<std::uint64_t>(std::max(a, b));
  // The shared cache is only read while tasks run; a task keeps what it learns until the join.
  const auto known = adjacent_.find(key);
  if (known != adjacent_.end()) return known->second;
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (task == nullptr) {
    const bool adjacent = sharesVertex(*topology_, na.first, na.last, nb.first, nb.last, mark_);
    adjacent_.emplace(key, adjacent);
    return adjacent;
  }
  const auto learned = task->learned.find(key);
  if (learned != task->learned.end()) return learned->second;
  const bool adjacent = sharesVertex(*topology_, na.first, na.last, nb.first, nb.last, task->mark);
  task->learned.emplace(key, adjacent);
  return adjacent;
}

void PairSearch::leafPair(int i, int j, unsigned tests, Task& task) const {
  if (dirty_ != nullptr && !dirty_triangle_[order_[i]] && !dirty_triangle_[order_[j]]) return;
  const SurfaceTopology& topology = *topology_;
  const int a = order_[i], b = order_[j];
  if ((tests & kEdges) && tight_box_[i].overlaps(tight_box_[j])) {
    ++task.triangle_pairs;
    for (const int* e = topology.ownedEdgesBegin(a); e != topology.ownedEdgesEnd(a); ++e) {
      const auto& ea = topology.edge(*e);
      for (const int* f = topology.ownedEdgesBegin(b); f != topology.ownedEdgesEnd(b); ++f) {
        const auto& eb = topology.edge(*f);
        if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
        if (!edge_box_[*e].intersects(edge_box_[*f])) continue;
        task.out.push_back({PairKind::kEdgeEdge, {ea[0], ea[1], eb[0], eb[1]}});
      }
    }
  }
  if ((tests & kVerticesOfA) && owned_box_[i].overlaps(tight_box_[j])) vertexTriangle(a, b, task);
  if ((tests & kVerticesOfB) && owned_box_[j].overlaps(tight_box_[i])) vertexTriangle(b, a, task);
}

void PairSearch::vertexTriangle(int owner, int other, Task& task) const {
  const SurfaceTopology& topology = *topology_;
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const Eigen::AlignedBox3d& other_box = triangle_box_[other];
  for (const int* v = topology.ownedVerticesBegin(owner); v != topology.ownedVerticesEnd(owner);
       ++v) {
    if (topology.triangleHas(other, *v) || !vertex_box_[*v].intersects(other_box)) continue;
    ++task.vertex_pairs;
    task.out.push_back({PairKind::kVertexTriangle, {*v, tri(0, other), tri(1, other), tri(2, other)}});
  }
}

}  // namespace cloth_sim
