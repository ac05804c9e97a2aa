#include "cloth_sim/core/collision/contact_forces.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {
namespace {

/// A point within this many radii of a sphere (along its relative path) becomes a candidate.
constexpr double kMarginRadii = 0.5;
/// Jacobi relaxation on top of mass splitting (contacts also share cloth around them).
constexpr double kRelaxation = 0.5;

/// Contact normal for a point whose path relative to a sphere of radius @p r goes from @p a to
/// @p b; false if the path stays farther than @p reach from the centre.
bool sweptNormal(const Vec3& a, const Vec3& b, double r, double reach, Vec3& normal, bool& swept) {
  swept = false;
  const Vec3 path = b - a;
  const double len2 = path.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(path) / len2, 0.0, 1.0) : 0.0;
  if ((a + t * path).norm() > reach) return false;
  // A sweep (the point moves by more than half a radius relative to the sphere, or would pass
  // its centre): push it back out where it entered. A resting or rolling contact uses the
  // radial direction: the entry point of a slow slide lies ahead of the contact and would tilt
  // the force into a drag.
  const bool sweep = std::sqrt(len2) > 0.5 * r || b.dot(a) <= 0.0;
  if (sweep && a.squaredNorm() > r * r && len2 > 0.0) {
    const double enter = sphereEntry(a, path, r);
    if (enter >= 0.0) {
      normal = (a + enter * path).normalized();
      swept = true;
      return true;
    }
  }
  if (b.norm() > 1e-12) normal = b.normalized();
  else normal = a.norm() > 1e-12 ? Vec3(a.normalized()) : Vec3::UnitZ();
  return true;
}

/// Barycentric weights of @p q, a point of triangle (a, b, c).
std::array<double, 3> barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1), den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0.0)) return {1.0, 0.0, 0.0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {std::max(0.0, 1.0 - v - w), std::max(0.0, v), std::max(0.0, w)};
}

/// The position (m) stored at @p offset of a node buffer.
Vec3 nodeAt(const NodeBuffer& x, int offset) { return Vec3(x[offset], x[offset + 1], x[offset + 2]); }

}  // namespace

void ContactForces::boxFeatures(const Model& model, const Points& y) {
  // Shared by every dynamic sphere of the step: one box per movable feature, built once.
  features_.clear();
  feature_boxes_.clear();
  std::vector<Eigen::AlignedBox3d> vertex_box(y.cols());
  for (Eigen::Index i = 0; i < y.cols(); ++i) {
    vertex_box[i].extend(Vec3(start_.col(i))).extend(Vec3(y.col(i)));
  }
  auto add = [&](const std::array<int, 3>& v, int count) {
    Eigen::AlignedBox3d box;
    for (int j = 0; j < count; ++j) {
      if (!movable_[v[j]]) return;  // a pinned vertex cannot be pushed
      box.extend(vertex_box[v[j]]);
    }
    features_.push_back({v, count});
    feature_boxes_.push_back(box);
  };
  if (model.triangles.cols() > 0) {
    for (Eigen::Index t = 0; t < model.triangles.cols(); ++t) {
      add({model.triangles(0, t), model.triangles(1, t), model.triangles(2, t)}, 3);
    }
  } else {
    for (Eigen::Index i = 0; i < y.cols(); ++i) add({static_cast<int>(i), 0, 0}, 1);
  }
}

void ContactForces::addCandidates(std::size_t k, const Points& y) {
  const Points& start = start_;
  const Body& body = bodies_[k];
  const double reach = body.radius * (1.0 + kMarginRadii);
  Eigen::AlignedBox3d swept;
  swept.extend(body.old).extend(body.predicted);
  swept.min().array() -= reach;
  swept.max().array() += reach;
  std::set<std::array<int, 3>> seen;  // a feature (vertex, edge, face) shared by triangles
  auto consider = [&](const std::array<int, 3>& v, int count) {
    Contact c{v, {1.0, 0.0, 0.0}, static_cast<int>(k), Vec3::UnitZ(), 0.0, 0.0};
    if (count == 3) {
      // The triangle's point closest to the sphere, as barycentric weights for the step.
      const Vec3 q = closestPointOnTriangle(body.predicted, y.col(v[0]), y.col(v[1]), y.col(v[2]));
      c.weight = barycentric(q, y.col(v[0]), y.col(v[1]), y.col(v[2]));
    }
    std::array<int, 3> feature{-1, -1, -1};
    for (int j = 0, n = 0; j < 3; ++j) {
      if (c.weight[j] > 1e-9) feature[n++] = c.vertex[j];
      else c.weight[j] = 0.0;
    }
    std::sort(feature.begin(), feature.end());
    if (!seen.insert(feature).second) return;
    Vec3 at_start = Vec3::Zero(), at_end = Vec3::Zero();
    for (int j = 0; j < 3; ++j) {
      at_start += c.weight[j] * start.col(c.vertex[j]);
      at_end += c.weight[j] * y.col(c.vertex[j]);
    }
    if (!sweptNormal(at_start - body.old, at_end - body.predicted, body.radius, reach, c.normal,
                     c.sweep)) {
      return;
    }
    c.triangle = count == 3;
    c.source = body.id;
    contacts_.push_back(c);
  };
  for (std::size_t f = 0; f < features_.size(); ++f) {
    if (feature_boxes_[f].intersects(swept)) consider(features_[f].vertex, features_[f].count);
  }
}

void ContactForces::addStillCandidates(const Model& model, const Points& y) {
  // Reach beyond the step's free motion: about a quarter spacing, what the springs move a
  // particle within one step at most in a resting drape.
  double spacing = 0.0;
  for (std::size_t k = 0; k < model.springs.size(); ++k) spacing += model.springs.rest_length[k];
  const double margin = model.springs.size() > 0 ? 0.25 * spacing / model.springs.size() : 0.0;
  for (Eigen::Index p = 0; p < y.cols(); ++p) {
    if (!movable_[p]) continue;
    const Vec3 start = start_.col(p);
    const double reach = (Vec3(y.col(p)) - start).norm() + margin;
    auto add = [&](const Vec3& normal, const Vec3& anchor, int source, double mu) {
      Contact c{{static_cast<int>(p), static_cast<int>(p), static_cast<int>(p)}, {1.0, 0.0, 0.0}, -1,
                normal, 0.0, 0.0};
      c.anchor = anchor;
      c.source = source;
      c.mu = mu;
      contacts_.push_back(c);
    };
    if (ground_.enabled && start.z() < ground_.height + reach) {
      add(Vec3::UnitZ(), Vec3(start.x(), start.y(), ground_.height), stillSource(-1), ground_.friction);
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      Vec3 point, normal;
      if (meshes_[m]->nearest(start, reach + meshes_[m]->thickness(), point, normal)) {
        add(normal, point + meshes_[m]->thickness() * normal, stillSource(static_cast<int>(m)),
            meshes_[m]->friction());
      }
    }
  }
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
  for (Contact& c : contacts_) {
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
  }
  indexVertices(particle_node);
  placeBodies();
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
  touched_force_.assign(touched_.size(), Vec3::Zero());
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
  for (Contact& c : contacts_) relinearize(c, x);
  for (Contact& c : contacts_) {
    c.lambda = std::max(0.0, c.lambda - kRelaxation * gap(c, x) / c.response);
    const double mu = c.body < 0 ? c.mu : bodies_[c.body].friction;
    if (mu <= 0.0) continue;
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
  }
  placeBodies();
}

void ContactForces::addForces(NodeBuffer& rhs) const {
  // The cloth's step M (x - y) + h_i^2 grad E(x) = h_i^2 f: the forces enter with h_i^2.
  const double h2 = implicit_h_ * implicit_h_;
  // Summed per vertex first, then added: the same sums (to the bit) as a separate force field.
  std::fill(touched_force_.begin(), touched_force_.end(), Vec3::Zero());
  for (const Contact& c : contacts_) {
    if (c.lambda <= 0.0) continue;
    const Vec3 force = c.lambda * c.normal + c.friction;
    for (int j = 0; j < 3; ++j) {
      if (c.weight[j] > 0.0) touched_force_[c.slot[j]] += (h2 * c.weight[j]) * force;
    }
  }
  for (std::size_t t = 0; t < touched_.size(); ++t)
    for (int d = 0; d < 3; ++d) rhs[touched_[t] + d] += touched_force_[t][d];
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
    if (!stick || c.mu <= 0.0) continue;
    const Vec3 moved = positions.col(p) - start_.col(p);
    const Vec3 slip = moved - moved.dot(c.normal) * c.normal;
    // The friction that would cancel what the iterations left of the slip (one full projected
    // Jacobi step): inside the cone the contact sticks, and that slip is taken out, so a resting
    // cloth never creeps; outside it slides as the solve left it.
    if ((c.friction - slip / c.response).norm() > c.mu * c.lambda) continue;
    positions.col(p) -= slip;
    // d v_{n+1} / d x_{n+1} = 1 / h_i for implicit Euler (h_i = h) and BDF2.
    velocities.col(p) -= slip / implicit_h_;
    ++stuck;
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
}

int ContactForces::activeCount() const {
  int active = 0;
  for (const Contact& c : contacts_) active += c.lambda > 0.0 ? 1 : 0;
  return active;
}

}  // namespace cloth_sim
