/// @file contact_forces.h
/// Contact forces solved inside the implicit step (two-way coupling with dynamic spheres).
#pragma once

#include <array>
#include <map>
#include <utility>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/model/model.h"

namespace cloth_sim {

/// Normal contact forces between the cloth surface and dynamic spheres, as unknowns of the
/// implicit Euler step next to the positions:
///
///   M (x - y) + h^2 grad E(x) = h^2 sum_k lambda_k J_k^T n_k,   (cloth)
///   M_s (c - y_s)             = -h^2 sum_k lambda_k n_k,        (each dynamic sphere)
///   lambda_k >= 0,  gap_k = (J_k x - c) . n_k - r >= 0,  lambda_k gap_k = 0,
///
/// where contact k touches the closest point of a cloth triangle to the sphere
/// (J_k x = sum_j w_j x_j, barycentric weights; one contact per distinct face, edge or vertex),
/// so a sphere slides smoothly over the triangles and cannot slip between particles. Before
/// each iteration every contact is linearised again at the current iterate (the triangle's
/// closest point and the radial normal n_k): the fixed point is the contact with the real
/// sphere (a linearisation frozen for a step made the cloth flicker between two states under a
/// resting ball, and its leading-edge normals dragged a rolling one). A sweep contact (the
/// point moves more than half a radius relative to the sphere within the step, or would pass
/// its centre: a fast sphere) keeps, for the step, the normal where its path entered the
/// sphere: the sphere pushes the cloth ahead of itself instead of through it (continuous
/// detection).
///
/// An iterative solver calls update(x) and addForces(rhs) before each global solve: a projected
/// Jacobi step lambda <- max(0, lambda - gap / (h^2 compliance)), with compliance the point's
/// (sum_j w_j^2 (A^-1)_jj from the solver's matrix, times the number of contacts sharing each
/// vertex) plus the sphere's (number of its contacts / M_s): mass splitting, so the contacts
/// updated together do not overshoot together (Tonge et al. 2012). The force reaches the
/// neighbours of the contact through the global solve, so a sphere feels the cloth's tension,
/// not just the penetration of one step. Forces are warm-started from the previous step (a
/// resting contact converges over steps). Linear momentum is conserved exactly: the sphere
/// receives minus what the cloth receives.
class ContactForces {
 public:
  /// The colliders and the movable-particle mask of the coming steps (Simulation sets them).
  void bind(const Colliders* colliders, const std::vector<char>* movable) {
    colliders_ = colliders;
    movable_ = movable;
  }
  /// Prepares a step (called by the solver) from the start positions, the predicted ones @p y
  /// and each particle's @p compliance (1/kg: displacement per unit of right-hand side).
  /// Dynamic spheres are at their free end-of-step positions (Colliders::advance).
  void begin(const Model& model, const Points& start, const Points& y,
             const Eigen::VectorXd& compliance);
  /// Projected Jacobi update of the forces from the gaps of @p x, then the spheres' positions.
  void update(const Points& x);
  /// rhs (3 x N) += h^2 lambda w_j n for every active contact and touched vertex j.
  void addForces(Points& rhs) const;
  /// Writes the dynamic spheres' end-of-step positions and velocities into @p colliders and
  /// keeps the forces for the next step's warm start.
  void finish(Colliders& colliders);

  bool empty() const { return contacts_.empty(); }

 private:
  struct Contact {
    std::array<int, 3> vertex;     ///< touched vertices (unused slots: weight 0)
    std::array<double, 3> weight;  ///< barycentric weights of the contact point
    int body;                      ///< index into bodies_
    Vec3 normal;                   ///< unit, from the sphere to the point
    double lambda;                 ///< N, >= 0
    double compliance;             ///< 1/kg
    Vec3 friction = Vec3::Zero();  ///< N, tangential, |friction| <= mu lambda
    Vec3 start = Vec3::Zero();     ///< contact point at the start of the step (m)
    bool triangle = false;         ///< vertex holds a whole triangle (weights may move)
    bool sweep = false;            ///< the sphere swept over the point: entry normal kept
  };
  struct Body {
    int id;
    double radius;
    double inv_mass;
    Vec3 predicted;  ///< free end-of-step centre y_s (m)
    Vec3 old;        ///< centre at the start of the step (m)
    Vec3 center;     ///< current end-of-step estimate (m)
    Vec3 spin;       ///< angular velocity at the start of the step (rad/s)
    double inv_inertia;
    double friction; ///< Coulomb mu of the sphere
  };
  void addCandidates(std::size_t body, const Model& model, const Points& start, const Points& y);
  /// Signed distance (m) of the contact point beyond the contact's half-space.
  double gap(const Contact& c, const Points& x) const;
  void placeBodies();
  void relinearize(Contact& c, const Points& x) const;

  const Colliders* colliders_ = nullptr;
  const std::vector<char>* movable_ = nullptr;
  std::vector<Contact> contacts_;
  std::vector<Body> bodies_;
  double h_ = 0.0;
  std::map<std::pair<int, int>, double> vertex_force_;  ///< (sphere id, vertex) -> N
};

}  // namespace cloth_sim
