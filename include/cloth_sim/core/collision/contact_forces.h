/// @file contact_forces.h
/// Contact forces solved inside the implicit step (two-way coupling with dynamic spheres).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/linalg/node_buffer.h"
#include "cloth_sim/core/linalg/parallel.h"
#include "cloth_sim/core/model/model.h"

namespace cloth_sim {

/// Normal contact forces between the cloth and the colliders, as unknowns of the implicit
/// Euler step next to the positions. The still colliders (ground, mesh obstacles) get one
/// contact per particle near them: the half-space n . (x_p - a) >= 0 of the collider's nearest
/// point a (offset by the mesh's thickness) and direction n from it to the particle at the start
/// of the step (a face normal, or radial round an edge), with the same projected Jacobi update
/// and no reaction. Why: the solve then moves a particle pulled into a wall along the wall (a
/// spring hooked round a box's top edge shortens by lifting its side end) instead of into it,
/// where the post-solve projection only cancelled the move, step after step. Still contacts
/// use the compliance 1/m_p (see begin()): a sheet lying on a plane is pushed by all its
/// contacts at once, a mode the cloth does not resist. Kinematic spheres keep the post-solve
/// projection only. Dynamic spheres:
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
/// Simulation starts a step with beginStep; an iterative solver then calls begin (once) and
/// update(x), addForces(rhs) before each global solve, on its own node-ordered buffers: a projected
/// Jacobi step lambda <- max(0, lambda - gap / (h_i^2 c_point + h^2 c_sphere)), with c_point the
/// point's
/// (sum_j w_j^2 (A^-1)_jj from the solver's matrix, times the number of contacts sharing each
/// vertex) and c_sphere the sphere's (number of its contacts / M_s): mass splitting, so the contacts
/// updated together do not overshoot together (Tonge et al. 2012). The force reaches the
/// neighbours of the contact through the global solve, so a sphere feels the cloth's tension,
/// not just the penetration of one step. Forces are warm-started from the previous step (a
/// resting contact converges over steps). Linear momentum is conserved exactly: the sphere
/// receives minus what the cloth receives.
///
/// Self-contact pairs (SelfPair: a vertex and a triangle, or two edges, of the cloth itself)
/// enter the same way, with the constraint n . sum_k w_k x_k >= d on four particles whose
/// weights sum to zero: lambda <- max(0, lambda - 0.5 gap / r), r = h_i^2 sum_k w_k^2 c_k
/// (c_k: compliance times the pairs sharing the particle), and Coulomb friction f on the
/// closest points' slide, |f| <= mu lambda; the force w_k (lambda n + f) on each particle (so
/// their momentum sums to zero). The pairs are those the previous step's proximity stage held
/// (TriangleSelfContact::solvePairs), linearised at its end: the solve then finds the springs'
/// balance with the layers apart, where a push after the solve alone stretched springs that
/// the next two iterations let go of only partly, and a pile gained energy until it blew up
/// (docs/method.md, "Self-contact in the solve").
class ContactForces {
 public:
  /// A self-contact constraint n . sum_k weight[k] x_{vertex[k]} >= distance on four particles
  /// of the cloth (weights sum to zero: a vertex against a triangle's point, or an edge's
  /// point against another's).
  struct SelfPair {
    std::array<int, 4> vertex{};
    std::array<double, 4> weight{};
    Vec3 normal = Vec3::Zero();  ///< unit, from the second primitive to the first
    double distance = 0.0;       ///< m, the distance the pair keeps
    double mu = 0.0;             ///< Coulomb coefficient of the cloth on itself
    bool edges = false;          ///< edge-edge (else vertex[0] against a triangle)
  };
  /// Swaps @p pairs with the self-contact pairs the next steps' begin() reads (kept as the
  /// warm start is: a copy of this object, as in a snapshot, keeps them).
  void swapSelfPairs(std::vector<SelfPair>& pairs) { self_pairs_.swap(pairs); }
  /// No self-contact pairs in the next steps (self-contact off, or in mode particles).
  void clearSelfPairs() { self_pairs_.clear(); }
  /// Wall time (s) of the self-contact pairs' set-up, updates and forces since the last call:
  /// self-contact's share of the solve (StepReport::self_contact_time).
  double takeSelfPairSeconds();
  /// Starts a step (Simulation): the dynamic spheres of @p colliders at their free end-of-step
  /// positions (Colliders::advance done) and the step's context, kept by value until the next
  /// beginStep.
  void beginStep(const CollisionStep& step, const Colliders& colliders);
  /// Finds the contacts of the step (called by the solver) from the predicted positions @p y
  /// (3 x N, particle order) and each particle's @p compliance (1/kg: displacement per unit of
  /// right-hand side). From here on the iterates are the solver's node buffers: particle p is at
  /// doubles kNodeStride * @p particle_node[p] + 0, 1, 2. @p implicit_h (s) is the cloth step's
  /// h_i, the step of its h_i^2 E(x) term and matrix M + h_i^2 L (ImplicitStepProblem): h for
  /// implicit Euler, 2h/3 for BDF2 (docs/method.md, "BDF2"). The forces enter the cloth's
  /// right-hand side with h_i^2 and the spheres' step with h^2, so a sphere's impulse h lambda
  /// equals what BDF2's momentum recurrence hands the cloth over the following steps.
  void begin(const Model& model, const Points& y, const Eigen::VectorXd& compliance,
             const std::vector<int>& particle_node, double implicit_h);
  /// Projected Jacobi update of the forces from the gaps of @p x, then the spheres' positions.
  void update(const NodeBuffer& x);
  /// rhs += h_i^2 (lambda n + friction) w_j for every active contact and touched vertex j.
  void addForces(NodeBuffer& rhs) const;
  /// Writes the dynamic spheres' end-of-step positions and velocities into @p colliders and
  /// keeps the forces for the next step's warm start.
  void finish(Colliders& colliders);

  /// Threads of the contact loops (detection, update, forces; SolverSettings::threads resolved).
  /// The loops' blocks are fixed, so the results do not depend on it.
  void setThreads(int threads) { threads_ = threads; }

  /// Friction of the still contacts (ground, mesh obstacles) completed after the solve, one
  /// full projected Jacobi step on the positions the iterations reached (@p positions, 3 x N,
  /// particle order): a contact whose friction can cancel what is left of its slip within the
  /// cone mu lambda sticks (that slip is taken out of its end position), the others slide with
  /// the friction mu lambda against it; each velocity changes by its position's change / h_i.
  /// So a cloth at rest inside the friction cone does not creep and one outside slides at
  /// g_t - mu g_n. Only with @p stick: the test weighs the slip the iterations left against the
  /// friction they reached, which after a fixed handful of iterations is far from the solution
  /// (a cloth dragged over a box stuck to its top and stretched 300 %); Simulation asks for it
  /// when the iterations stop at a tolerance (SolverInput::iteration_tolerance > 0). Returns
  /// the contacts that stuck.
  /// Under a multistep integrator (BDF2: h_i < h) every pushing still contact also restarts its
  /// particle's velocity along the normal, and that of @p history_velocities (State::
  /// previous_velocities, or null), as resolveCollisions does: contacts are inelastic. A
  /// contact that sticks restarts both whole, as implicit Euler's (x_{n+1} - x_n) / h: its
  /// tangential stop is as sudden, and BDF2 would send it back the way it came.
  int completeFriction(Points& positions, Points& velocities, Points* history_velocities,
                       bool stick) const;

  bool empty() const { return contacts_.empty() && pairs_.empty(); }
  /// Adds to @p pushes (3 x N, N) the normal force the last solve's self-contact pairs put on
  /// each of their particles, w_k lambda n, also where a particle is hard pinned (it gets no
  /// force, but the pairs still push against it).
  void addSelfPushes(Points& pushes) const;
  /// Contacts of this step that push (lambda > 0): a contact point on a triangle, an edge or a
  /// vertex (spheres) or a particle (ground, mesh obstacles).
  int activeCount() const;
  /// Sets @p mask[i] (one per particle) for every particle an active contact or self pair of
  /// this step touches.
  void markTouched(std::vector<char>& mask) const;

 private:
  struct Contact {
    std::array<int, 3> vertex;     ///< touched vertices (unused slots: weight 0)
    std::array<double, 3> weight;  ///< barycentric weights of the contact point
    int body;                      ///< index into bodies_; -1: a still half-space (anchor)
    Vec3 normal;                   ///< unit, from the collider to the point
    double lambda;                 ///< N, >= 0
    /// m/N: the gap's change per unit force, h_i^2 times the cloth point's compliance plus h^2
    /// times the sphere's (mass splitting)
    double response;
    Vec3 friction = Vec3::Zero();  ///< N, tangential, |friction| <= mu lambda
    Vec3 start = Vec3::Zero();     ///< contact point at the start of the step (m)
    bool triangle = false;         ///< vertex holds a whole triangle (weights may move)
    bool sweep = false;            ///< the sphere swept over the point: entry normal kept
    std::array<int, 3> offset{};   ///< the vertices' first double in the node buffers
    std::array<int, 3> slot{};     ///< the vertices' index in touched_
    Vec3 anchor = Vec3::Zero();    ///< still contact: a point of its plane (m)
    double mu = 0.0;               ///< still contact: the collider's Coulomb coefficient
    int source = 0;                ///< warm-start key: a sphere's id, or stillSource()
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
  /// Warm-start key of a still collider (-1: the ground, m >= 0: mesh obstacle m), below
  /// every sphere id (>= 0).
  static int stillSource(int collider) { return -2 - collider; }
  /// A cloth feature a sphere may touch: a triangle (count 3) or, without triangles, a vertex.
  struct Feature {
    std::array<int, 3> vertex;
    int count;
  };
  // Detection (contact_detection.cpp).
  /// Lists the features with no pinned vertex and their boxes over the step (start to @p y).
  void boxFeatures(const Model& model, const Points& y);
  /// Adds the contacts of dynamic sphere @p body with the features near its swept path.
  void addCandidates(std::size_t body, const Points& y);
  /// Vertex contacts with the ground and the mesh obstacles (still half-spaces, no reaction).
  void addStillCandidates(const Model& model, const Points& y);
  /// Barycentric weights of @p q, a point of triangle (a, b, c).
  static std::array<double, 3> barycentric(const Vec3& q, const Vec3& a, const Vec3& b,
                                           const Vec3& c);
  /// Signed distance (m) of the contact point beyond the contact's half-space.
  double gap(const Contact& c, const NodeBuffer& x) const;
  void placeBodies();
  void relinearize(Contact& c, const NodeBuffer& x) const;
  /// Sets the contacts' offsets and slots; lists the touched vertices.
  void indexVertices(const std::vector<int>& particle_node);

  double h_ = 0.0;           ///< s, the step (the spheres are integrated over it)
  double implicit_h_ = 0.0;  ///< s, the cloth step's h_i (begin)
  GroundPlane ground_;                                      ///< this step's ground
  std::vector<std::shared_ptr<const MeshObstacle>> meshes_; ///< this step's mesh obstacles
  std::vector<char> movable_;  ///< this step's movable mask (CollisionStep::movable)
  Points start_;               ///< this step's start positions (CollisionStep::start)
  std::vector<Contact> contacts_;
  std::vector<Body> bodies_;
  std::vector<Feature> features_;                    ///< boxFeatures' features
  std::vector<Eigen::AlignedBox3d> feature_boxes_;   ///< and their swept boxes (m)
  /// Node offsets of the vertices the contacts touch; per slot of touched_, its contact
  /// vertices (3 contact + j) in contact order, [slot_begin_[t], slot_begin_[t + 1]) of
  /// slot_entry_: addForces sums each vertex's forces in that order before they reach the
  /// right-hand side.
  std::vector<int> touched_;
  std::vector<int> slot_begin_, slot_entry_;
  std::vector<int> slot_of_;  ///< indexVertices' work buffer: a vertex's slot in touched_, or -1
  int threads_ = 1;
  /// Calls @p f(contact) for every contact, in fixed blocks on up to threads_ threads.
  template <typename F>
  void forEachContact(F&& f) {
    const BlockSplit split(contacts_.size(), 256);
    parallelFor(threads_, split.blocks(), [&](int b) {
      for (std::size_t k = split.begin(b); k < split.end(b); ++k) f(contacts_[k]);
    });
  }
  /// Key of vertex_force_: a contact's source (any int) and a vertex (>= 0).
  static std::uint64_t forceKey(int source, int vertex) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(source)) << 32) |
           static_cast<std::uint32_t>(vertex);
  }
  /// Last step's force on a vertex from one source: normal (N) and, for still contacts,
  /// friction (N, tangential), the warm start of the next step.
  struct Force {
    double normal = 0.0;
    Vec3 friction = Vec3::Zero();
  };
  std::unordered_map<std::uint64_t, Force> vertex_force_;  ///< forceKey(source, vertex) -> force

  /// A self pair in the solve.
  struct PairForce {
    SelfPair pair;
    double lambda = 0.0;    ///< N, >= 0
    double response = 0.0;  ///< m/N: h_i^2 sum_k w_k^2 c_k (mass splitting, as the contacts')
    Vec3 friction = Vec3::Zero();  ///< N, on the first primitive, |friction| <= mu lambda
    Vec3 start = Vec3::Zero();     ///< m, sum_k w_k x_k at the start of the step
    std::array<int, 4> offset{};  ///< the particles' first double in the node buffers
  };
  /// Lists pairs_ from self_pairs_ (begin): responses, offsets, warm starts.
  void beginPairs(const Eigen::VectorXd& compliance, const std::vector<int>& particle_node);
  std::vector<SelfPair> self_pairs_;  ///< swapSelfPairs' pairs
  std::vector<PairForce> pairs_;
  /// Last step's pair forces (N) summed on each pair's vertex[0], vertex pairs and edge pairs
  /// apart: the warm start, shared among this step's pairs on that particle.
  std::vector<double> vertex_pair_force_, edge_pair_force_;
  std::vector<int> pair_count_;  ///< beginPairs' work buffer
  mutable double self_pair_seconds_ = 0.0;
};

}  // namespace cloth_sim
