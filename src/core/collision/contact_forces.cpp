#include "cloth_sim/core/collision/contact_forces.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {
namespace {

/// Jacobi relaxation on top of mass splitting (contacts also share cloth around them).
constexpr double kRelaxation = 0.5;

/// The position (m) stored at @p offset of a node buffer.
Vec3 nodeAt(const NodeBuffer& x, int offset) { return Vec3(x[offset], x[offset + 1], x[offset + 2]); }

/// Adds the wall time from its construction to @p total (s).
class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~Stopwatch() {
    total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

std::array<double, 3> ContactForces::barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1), den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0.0)) return {1.0, 0.0, 0.0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {std::max(0.0, 1.0 - v - w), std::max(0.0, v), std::max(0.0, w)};
}

void ContactForces::beginStep(const CollisionStep& step, const Colliders& colliders) {
  h_ = step.h;
  movable_ = step.movable;
  start_ = step.start;
  contacts_.clear();
  bodies_.clear();
  ground_ = colliders.ground();
  meshes_ = colliders.meshes();
  for (const SphereCollider& s : colliders.spheres()) {
    // Colliders::advance already moved each sphere to its free end-of-step position.
    bodies_.push_back(Body{s.id, s.radius, s.isDynamic() ? 1.0 / s.mass : 0.0, s.center,
                           Vec3(s.center - h_ * s.velocity), s.center, s.angular_velocity,
                           s.isDynamic() ? 1.0 / s.inertia() : 0.0, s.friction});
  }
}

void ContactForces::begin(const Model& model, const Points& y, const Eigen::VectorXd& compliance,
                          const std::vector<int>& particle_node, double implicit_h) {
  const Points& start = start_;
  implicit_h_ = implicit_h;
  contacts_.clear();
  const bool any_dynamic = std::any_of(bodies_.begin(), bodies_.end(),
                                       [](const Body& b) { return b.inv_mass > 0.0; });
  if (any_dynamic) boxFeatures(model, y);
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    // Kinematic spheres keep the post-solve projection (in the solve a soft cloth sagged past
    // 100 % strain on one in the stability sweep).
    if (bodies_[k].inv_mass > 0.0) addCandidates(k, y);
  }
  addStillCandidates(model, y);
  // Mass splitting: count the contacts sharing each vertex and each sphere.
  std::vector<int> per_vertex(y.cols(), 0), per_body(bodies_.size(), 0);
  for (const Contact& c : contacts_) {
    if (c.body >= 0) ++per_body[c.body];
    for (int j = 0; j < 3; ++j) {
      if (c.weight[j] > 0.0) ++per_vertex[c.vertex[j]];
    }
  }
  forEachContact([&](Contact& c) {
    c.start = Vec3::Zero();
    for (int j = 0; j < 3; ++j) c.start += c.weight[j] * start.col(c.vertex[j]);
    // The gap's response to a unit force: the cloth's part moves by h_i^2 (its right-hand side
    // carries h_i^2 lambda), the sphere's by h^2 (it is integrated over h, placeBodies).
    const double hi2 = implicit_h_ * implicit_h_, h2 = h_ * h_;
    if (c.body < 0) {
      // A still contact per particle: a sheet lying on a plane is pushed by all of them at
      // once, a mode the cloth's stiffness does not resist, so the point compliance (A^-1)_pp
      // would overshoot it many times over; 1/m_p bounds every mode (A >= M).
      c.response = hi2 * per_vertex[c.vertex[0]] / model.mass[c.vertex[0]];
    } else {
      c.response = h2 * per_body[c.body] * bodies_[c.body].inv_mass;
      for (int j = 0; j < 3; ++j) {
        if (c.weight[j] > 0.0) {
          c.response +=
              hi2 * c.weight[j] * c.weight[j] * per_vertex[c.vertex[j]] * compliance[c.vertex[j]];
        }
      }
    }
    // Warm start from last step's force on each touched vertex, shared among this step's
    // contacts on it: continuous when a contact moves between a vertex and a face.
    c.lambda = 0.0;
    bool warm = false;
    for (int j = 0; j < 3; ++j) {
      if (c.weight[j] <= 0.0) continue;
      const auto it = vertex_force_.find(forceKey(c.source, c.vertex[j]));
      if (it == vertex_force_.end()) continue;
      warm = true;
      c.lambda += c.weight[j] * it->second.normal / per_vertex[c.vertex[j]];
      // A still contact's friction too: a cloth at rest on a slope is held by last step's
      // force from the first iteration on, not rebuilt from zero (which let it creep).
      if (c.body < 0) c.friction += c.weight[j] * it->second.friction / per_vertex[c.vertex[j]];
    }
    if (!warm && c.body < 0) {
      // A new still contact starts from the normal force that would stop the particle's free
      // motion y + h_i^2 g at the surface (springs aside): a sheet laid on a plane carries its
      // weight from its first iteration. Its friction starts from zero: a guess from the free
      // motion alone opposed what the springs then did, and after a fixed handful of
      // iterations a cloth dragged over a box stretched 37 % where the reference stayed at 1 %.
      const int p = c.vertex[0];
      const Vec3 free_move = Vec3(y.col(p)) + hi2 * model.gravity - start.col(p);
      c.lambda = std::max(0.0, -(Vec3(start.col(p)) + free_move - c.anchor).dot(c.normal)) /
                 c.response;
    }
    c.friction -= c.friction.dot(c.normal) * c.normal;
    const double cap = c.mu * c.lambda;
    if (c.friction.norm() > cap) c.friction *= cap / c.friction.norm();
  });
  indexVertices(particle_node);
  placeBodies();
  beginPairs(compliance, particle_node);
}

void ContactForces::beginPairs(const Eigen::VectorXd& compliance,
                               const std::vector<int>& particle_node) {
  pairs_.clear();
  if (self_pairs_.empty()) return;
  Stopwatch watch(self_pair_seconds_);
  const std::size_t n = static_cast<std::size_t>(start_.cols());
  if (vertex_pair_force_.size() != n) {
    vertex_pair_force_.assign(n, 0.0);
    edge_pair_force_.assign(n, 0.0);
  }
  // Mass splitting over the pairs sharing each particle; and the pairs sharing each warm-start
  // key (vertex[0] of each kind: a vertex's weight is shared by its pairs, as a contact's).
  pair_count_.assign(3 * n, 0);
  for (const SelfPair& p : self_pairs_) {
    for (int k = 0; k < 4; ++k) ++pair_count_[p.vertex[k]];
    ++pair_count_[(p.edges ? 2 : 1) * n + p.vertex[0]];
  }
  const double hi2 = implicit_h_ * implicit_h_;
  pairs_.reserve(self_pairs_.size());
  for (const SelfPair& p : self_pairs_) {
    PairForce f;
    f.pair = p;
    for (int k = 0; k < 4; ++k) {
      const int v = p.vertex[k];
      f.offset[k] = kNodeStride * particle_node[v];
      f.start += p.weight[k] * start_.col(v);
      if (movable_[v]) f.response += hi2 * p.weight[k] * p.weight[k] * pair_count_[v] * compliance[v];
    }
    if (!(f.response > 0.0)) continue;  // four pinned particles: nothing to move
    const std::vector<double>& last = p.edges ? edge_pair_force_ : vertex_pair_force_;
    f.lambda = last[p.vertex[0]] / pair_count_[(p.edges ? 2 : 1) * n + p.vertex[0]];
    pairs_.push_back(f);
  }
}

double ContactForces::takeSelfPairSeconds() {
  const double seconds = self_pair_seconds_;
  self_pair_seconds_ = 0.0;
  return seconds;
}

void ContactForces::indexVertices(const std::vector<int>& particle_node) {
  touched_.clear();
  slot_of_.assign(particle_node.size(), -1);  // vertex -> slot, in order of first touch
  for (Contact& c : contacts_) {
    for (int j = 0; j < 3; ++j) {
      c.offset[j] = kNodeStride * particle_node[c.vertex[j]];
      int& slot = slot_of_[c.vertex[j]];
      if (slot < 0) {
        slot = static_cast<int>(touched_.size());
        touched_.push_back(c.offset[j]);
      }
      c.slot[j] = slot;
    }
  }
  // Each slot's contact vertices, in contact order (a counting sort).
  slot_begin_.assign(touched_.size() + 1, 0);
  for (const Contact& c : contacts_)
    for (int j = 0; j < 3; ++j) ++slot_begin_[c.slot[j] + 1];
  for (std::size_t t = 0; t < touched_.size(); ++t) slot_begin_[t + 1] += slot_begin_[t];
  slot_entry_.resize(3 * contacts_.size());
  std::vector<int> next(slot_begin_.begin(), slot_begin_.end() - 1);
  for (std::size_t k = 0; k < contacts_.size(); ++k)
    for (int j = 0; j < 3; ++j) slot_entry_[next[contacts_[k].slot[j]]++] = static_cast<int>(3 * k + j);
}

void ContactForces::placeBodies() {
  for (Body& b : bodies_) b.center = b.predicted;
  for (const Contact& c : contacts_) {
    if (c.body < 0) continue;
    Body& b = bodies_[c.body];
    b.center -= (h_ * h_ * b.inv_mass) * (c.lambda * c.normal + c.friction);
  }
}

double ContactForces::gap(const Contact& c, const NodeBuffer& x) const {
  Vec3 point = Vec3::Zero();
  for (int j = 0; j < 3; ++j) {
    if (c.weight[j] > 0.0) point += c.weight[j] * nodeAt(x, c.offset[j]);
  }
  if (c.body < 0) return (point - c.anchor).dot(c.normal);
  const Body& b = bodies_[c.body];
  // Along the contact's normal: the sphere linearised at the last iterate (relinearize).
  return (point - b.center).dot(c.normal) - b.radius;
}

void ContactForces::relinearize(Contact& c, const NodeBuffer& x) const {
  // Re-linearise a resting/rolling contact at the current iterate: the triangle's closest point
  // and the radial normal. Sweep contacts keep their entry normal for the whole step.
  if (c.sweep || c.body < 0) return;
  const Body& b = bodies_[c.body];
  if (c.triangle) {
    const Vec3 a = nodeAt(x, c.offset[0]), b1 = nodeAt(x, c.offset[1]), b2 = nodeAt(x, c.offset[2]);
    c.weight = barycentric(closestPointOnTriangle(b.center, a, b1, b2), a, b1, b2);
  }
  Vec3 point = Vec3::Zero();
  for (int j = 0; j < 3; ++j) point += c.weight[j] * nodeAt(x, c.offset[j]);
  const Vec3 d = point - b.center;
  if (d.norm() > 1e-12) c.normal = d.normalized();
}

void ContactForces::update(const NodeBuffer& x) {
  const double h2 = h_ * h_;
  forEachContact([&](Contact& c) { relinearize(c, x); });
  forEachContact([&](Contact& c) {  // each contact on its own: any blocks, any threads
    c.lambda = std::max(0.0, c.lambda - kRelaxation * gap(c, x) / c.response);
    const double mu = c.body < 0 ? c.mu : bodies_[c.body].friction;
    if (mu <= 0.0) return;
    // Slip of the contact point over the step, relative to the collider's surface point.
    Vec3 point = Vec3::Zero();
    for (int j = 0; j < 3; ++j) point += c.weight[j] * nodeAt(x, c.offset[j]);
    Vec3 slip = point - c.start;
    double response = c.response;
    if (c.body >= 0) {
      const Body& b = bodies_[c.body];
      slip -= (b.center - b.old) + h_ * b.spin.cross(b.radius * c.normal);
      // The spin's response adds h^2 r^2 / I (r = radius) to the tangential response.
      response += h2 * b.radius * b.radius * b.inv_inertia;
    }
    const Vec3 tangential = slip - slip.dot(c.normal) * c.normal;
    c.friction -= kRelaxation * tangential / response;
    c.friction -= c.friction.dot(c.normal) * c.normal;
    const double cap = mu * c.lambda, size = c.friction.norm();
    if (size > cap) c.friction *= cap / size;
  });
  placeBodies();
  if (pairs_.empty()) return;
  Stopwatch watch(self_pair_seconds_);
  const BlockSplit split(pairs_.size(), 1024);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
      PairForce& f = pairs_[i];
      Vec3 g = Vec3::Zero();
      for (int k = 0; k < 4; ++k) g += f.pair.weight[k] * nodeAt(x, f.offset[k]);
      const double gap = f.pair.normal.dot(g) - f.pair.distance;
      f.lambda = std::max(0.0, f.lambda - kRelaxation * gap / f.response);
      if (f.pair.mu <= 0.0) continue;
      // The closest points' slide over the step, against Coulomb friction (as a still contact's).
      const Vec3 slip = g - f.start;
      const Vec3 n = f.pair.normal;
      f.friction -= kRelaxation * (slip - slip.dot(n) * n) / f.response;
      f.friction -= f.friction.dot(n) * n;
      const double cap = f.pair.mu * f.lambda, size = f.friction.norm();
      if (size > cap) f.friction *= cap / size;
    }
  });
}

void ContactForces::addForces(NodeBuffer& rhs) const {
  // The cloth's step M (x - y) + h_i^2 grad E(x) = h_i^2 f: the forces enter with h_i^2.
  const double h2 = implicit_h_ * implicit_h_;
  // Summed per vertex first, in contact order, then added: the same sums (to the bit) as a
  // separate force field; each vertex (slot) on its own, so any blocks, any threads.
  const BlockSplit split(touched_.size(), 256);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t t = split.begin(b); t < split.end(b); ++t) {
      Vec3 sum = Vec3::Zero();
      for (int e = slot_begin_[t]; e < slot_begin_[t + 1]; ++e) {
        const Contact& c = contacts_[slot_entry_[e] / 3];
        const int j = slot_entry_[e] % 3;
        if (c.lambda <= 0.0 || !(c.weight[j] > 0.0)) continue;
        sum += (h2 * c.weight[j]) * (c.lambda * c.normal + c.friction);
      }
      for (int d = 0; d < 3; ++d) rhs[touched_[t] + d] += sum[d];
    }
  });
  if (pairs_.empty()) return;
  Stopwatch watch(self_pair_seconds_);
  for (const PairForce& f : pairs_) {  // in pair order: the same sums on any thread count
    if (f.lambda <= 0.0 && f.friction.isZero(0.0)) continue;
    for (int k = 0; k < 4; ++k) {
      if (!movable_[f.pair.vertex[k]]) continue;
      const Vec3 force = (h2 * f.pair.weight[k]) * (f.lambda * f.pair.normal + f.friction);
      for (int d = 0; d < 3; ++d) rhs[f.offset[k] + d] += force[d];
    }
  }
}

void ContactForces::finish(Colliders& colliders) {
  std::vector<SphereCollider>& spheres = colliders.mutableSpheres();
  std::vector<Vec3> torque(bodies_.size(), Vec3::Zero());
  for (const Contact& c : contacts_) {
    if (c.body < 0) continue;
    // The cloth pushes the sphere with -(lambda n + friction) at r n from its centre.
    torque[c.body] += (bodies_[c.body].radius * c.normal).cross(-c.friction);
  }
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    if (bodies_[k].inv_mass == 0.0) continue;
    const Vec3 shift = bodies_[k].center - spheres[k].center;
    spheres[k].center = bodies_[k].center;
    spheres[k].velocity += shift / h_;
    spheres[k].angular_velocity += h_ * bodies_[k].inv_inertia * torque[k];
  }
  std::fill(vertex_pair_force_.begin(), vertex_pair_force_.end(), 0.0);
  std::fill(edge_pair_force_.begin(), edge_pair_force_.end(), 0.0);
  for (const PairForce& f : pairs_) {
    (f.pair.edges ? edge_pair_force_ : vertex_pair_force_)[f.pair.vertex[0]] += f.lambda;
  }
  vertex_force_.clear();
  for (const Contact& c : contacts_) {
    if (c.lambda <= 0.0) continue;
    for (int j = 0; j < 3; ++j) {
      if (c.weight[j] <= 0.0) continue;
      Force& f = vertex_force_[forceKey(c.source, c.vertex[j])];
      f.normal += c.lambda * c.weight[j];
      f.friction += c.friction * c.weight[j];
    }
  }
}

int ContactForces::completeFriction(Points& positions, Points& velocities,
                                    Points* history_velocities, bool stick) const {
  int stuck = 0;
  const bool multistep = implicit_h_ != h_;
  for (const Contact& c : contacts_) {
    if (c.body >= 0 || c.lambda <= 0.0) continue;
    const int p = c.vertex[0];
    if (stick && c.mu > 0.0) {
      const Vec3 moved = positions.col(p) - start_.col(p);
      const Vec3 slip = moved - moved.dot(c.normal) * c.normal;
      // The friction that would cancel what the iterations left of the slip (one full
      // projected Jacobi step): inside the cone the contact sticks, and that slip is taken out,
      // so a resting cloth never creeps; outside it slides as the solve left it.
      if ((c.friction - slip / c.response).norm() <= c.mu * c.lambda) {
        positions.col(p) -= slip;
        if (multistep) {
          // Stuck, the particle stops tangentially as suddenly as along the normal, and BDF2
          // would read that stop as a deceleration too and send it back (a cloth landing on a
          // table's edge crumpled there, measured): its velocity and history restart whole as
          // implicit Euler's. A sliding contact keeps BDF2's order tangentially.
          const Vec3 euler = (Vec3(positions.col(p)) - start_.col(p)) / h_;
          velocities.col(p) = euler;
          if (history_velocities != nullptr) history_velocities->col(p) = euler;
        } else {
          velocities.col(p) -= slip / h_;  // implicit Euler: d v_{n+1} / d x_{n+1} = 1 / h
        }
        ++stuck;
        continue;
      }
    }
    if (multistep) {
      // Inelastic along the normal: the velocity and its history restart as implicit Euler's
      // there (resolveCollisions' restartAlong says why).
      const double normal_speed = (Vec3(positions.col(p)) - start_.col(p)).dot(c.normal) / h_;
      velocities.col(p) += c.normal * (normal_speed - c.normal.dot(velocities.col(p)));
      if (history_velocities != nullptr) {
        Points& history = *history_velocities;
        history.col(p) += c.normal * (normal_speed - c.normal.dot(history.col(p)));
      }
    }
  }
  return stuck;
}

void ContactForces::markTouched(std::vector<char>& mask) const {
  for (const Contact& c : contacts_) {
    if (c.lambda <= 0.0) continue;
    for (int j = 0; j < 3; ++j) {
      if (c.weight[j] > 0.0) mask[c.vertex[j]] = 1;
    }
  }
  for (const PairForce& f : pairs_) {
    if (f.lambda <= 0.0) continue;
    for (int k = 0; k < 4; ++k) {
      if (f.pair.weight[k] != 0.0) mask[f.pair.vertex[k]] = 1;
    }
  }
}

void ContactForces::addSelfPushes(Points& pushes) const {
  for (const PairForce& f : pairs_) {
    if (f.lambda <= 0.0) continue;
    for (int k = 0; k < 4; ++k) {
      pushes.col(f.pair.vertex[k]) += (f.pair.weight[k] * f.lambda) * f.pair.normal;
    }
  }
}

int ContactForces::activeCount() const {
  int active = 0;
  for (const Contact& c : contacts_) active += c.lambda > 0.0 ? 1 : 0;
  return active;
}

}  // namespace cloth_sim
