/// @file local_step.h
/// Stateless kernels of the local step of local/global (Liu et al. 2013, sec. 4.2) over
/// structure-of-arrays springs and the padded node layout of supernodal_solves.h.
#pragma once

#include <vector>

#include "cloth_sim/core/linalg/node_buffer.h"
#include "cloth_sim/core/linalg/parallel.h"
#include "cloth_sim/core/linalg/supernodal_solves.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Nodes per block of the local step's fixed split (SpringTable::partition): 16 384 nodes
/// (128 x 128) make 32 blocks, enough for 16 threads; about 10 % of the springs then cross a
/// block boundary (docs/benchmark.md, "Threads").
constexpr int kLocalStepGrain = 512;

/// Nodes per block of the per-node loops (inertiaAndGravity, the copies of node buffers).
constexpr std::size_t kNodeGrain = 1024;

/// The springs of the local step, in a solver's node order (free nodes first, in the factor's
/// order, then hard-pinned ones), sorted by their first node for locality.
struct SpringTable {
  std::vector<int> a, b;           ///< end nodes; a spring with two pinned ends is not listed
  std::vector<double> weight;      ///< h^2 k r, kg m: the J d coefficient of eq. 12
  std::vector<double> half_k;      ///< k / 2, N/m
  std::vector<double> rest;        ///< r, m
  std::size_t size() const { return a.size(); }
  void add(int i, int j, double w, double k, double r);
  /// Sorts the springs by (min node, max node) so the local step walks memory forwards.
  /// Drops the partition.
  void sortByNode();

  /// Splits nodes [0, @p nodes) into blocks of @p grain (after sortByNode; every spring's nodes
  /// must be below @p nodes). Block b owns nodes [node_begin[b], node_begin[b + 1]): only it
  /// writes their rows of the right-hand side, so the blocks run on any threads at once. Its
  /// springs are [spring_begin[b], spring_begin[b + 1]), those whose lower node it owns
  /// (consecutive, the table being sorted). A spring whose upper node a later block owns (a
  /// boundary spring) leaves its push in a slot, [out_begin[b], out_begin[b + 1]) in spring
  /// order, which that block then adds (incoming_*: slot, node, +1 for an a end or -1 for a b
  /// end, in slot order). The split depends on the table and @p grain only, so every node's
  /// pushes add up in the same order on any number of threads. Without a partition (or before
  /// one) the table is one block.
  void partition(int nodes, int grain = kLocalStepGrain);
  /// Blocks of the partition (1 without one).
  int blocks() const { return node_begin.empty() ? 1 : static_cast<int>(node_begin.size()) - 1; }

  /// Per block (blocks() + 1 entries): its first node, first spring and first outgoing slot.
  std::vector<int> node_begin, spring_begin, out_begin;
  /// Per block, [incoming_begin[b], incoming_begin[b + 1]) of the slot, node and sign lists:
  /// the boundary pushes block b adds to its own nodes, in slot order.
  std::vector<int> incoming_begin, incoming_slot, incoming_node, incoming_sign;
  /// The boundary springs' pushes (kNodeStride doubles per slot): localStep3's work buffer.
  mutable NodeBuffer boundary_push;
};

/// Local step fused with the J d product (Liu et al. 2013, eqs. 10 and 12): for every spring,
/// d_s = r_s u with u = (x_a - x_b)/|x_a - x_b| (+x for a collapsed spring), and
/// rhs_a += h^2 k_s d_s, rhs_b -= h^2 k_s d_s. Returns the spring energy
/// sum_s 1/2 k_s (|x_a - x_b| - r_s)^2 (J) at @p x, which the objective g needs and which
/// costs nothing extra here. @p rhs must have a row for every node a spring refers to.
/// The blocks of the table's partition run on up to @p threads threads (parallel.h); the result
/// is the same, to the bit, for any @p threads (each node's pushes and the blocks' energies add
/// up in a fixed order).
double localStep3(const SpringTable& springs, const double* x, double* rhs, int threads = 1);

/// sum_s 1/2 k_s (|x_a - x_b| - r_s)^2 (J): the energy localStep3 returns, without the rhs
/// (the same sum per block, the same bits for any @p threads).
double springEnergy3(const SpringTable& springs, const double* x, int threads = 1);

/// sum_i m_i (1/2 |x_i - y_i|^2 - h^2 g . x_i) over @p count nodes (kg m^2): the inertia and
/// gravity part of the implicit Euler objective g (implicit_euler_problem.h). Blocks of
/// kNodeGrain nodes, summed in order: the same bits for any @p threads.
double inertiaAndGravity(const double* x, const double* y, const double* mass, int count,
                         const Vec3& gravity, double h2, int threads = 1);

/// @p to = @p from (node buffers of the same size), in blocks of kNodeGrain nodes on up to
/// @p threads threads.
void copyNodes(const NodeBuffer& from, NodeBuffer& to, int threads);

}  // namespace cloth_sim
