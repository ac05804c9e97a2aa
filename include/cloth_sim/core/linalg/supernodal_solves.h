/// @file supernodal_solves.h
/// Hand-written triangular solves for the global step of local/global (Liu et al. 2013, sec. 4):
/// one scalar factor L, three right-hand sides (x, y, z) solved in the same pass; in double or
/// in single precision, serially or with the independent subtrees of the elimination tree on
/// several threads (splitSolves).
#pragma once

#include <cstddef>
#include <vector>

#include "cloth_sim/core/linalg/cholmod_factor.h"

namespace cloth_sim {

/// Doubles per node in the padded node layout of the kernels: x, y, z and a pad slot kept at 0,
/// so one node is one 32-byte vector (AVX2) and its three coordinates share every load of L.
constexpr int kNodeStride = 4;

/// Widest supernode the kernels handle (their accumulators must fit in 16 AVX2 registers).
constexpr int kMaxSupernode = 8;

/// The solves' fixed split over the elimination tree (splitSolves): tasks that are disjoint sets
/// of supernodes, run phase by phase. Phase 0 holds the leaves (whole subtrees, the bulk of the
/// work), the next phases the separators above them, deepest first, the last one the root's. A
/// task touches the rows of its own columns and of its ancestors' (the outside rows): the
/// forward solve puts its updates of outside rows into the task's own slots of a scratch array,
/// which the owner of each row adds (gather) before its own supernodes; the backward solve first
/// copies the outside rows' final values into those slots. So the tasks of one phase share no
/// written memory, and every row's updates add up in one fixed order: the same bits on any
/// number of threads.
struct SolveTasks {
  struct Task {
    std::vector<int> supernodes;  ///< increasing (descendants before ancestors)
    int depth = 0;                ///< levels of bisection above it
    bool leaf = false;            ///< a whole subtree (else a separator)
    int parent = -1;              ///< the task of the separator above it (-1: none)
    int slot_begin = 0;           ///< its slots in the scratch: [slot_begin, slot_begin + size)
    std::vector<int> slot_row;    ///< the outside row of each of its slots
    /// Forward: before its supernodes, x[gather_row[k]] += scratch[gather_slot[k]], k in order.
    std::vector<int> gather_row, gather_slot;
  };
  std::vector<Task> tasks;        ///< in phase order
  std::vector<int> phase_begin;   ///< phase p: tasks [phase_begin[p], phase_begin[p + 1])
  int slots = 0;                  ///< scratch nodes in all

  /// Number of phases (0 without a split).
  int phases() const { return phase_begin.empty() ? 0 : static_cast<int>(phase_begin.size()) - 1; }

  /// How T threads run the tasks (schedule()): the subtrees below level k = ceil(log2 T) each
  /// go to one thread whole (its tasks in phase order: one synchronisation for all of them),
  /// the separators above them phase by phase. Any order that finishes a task's descendants
  /// first gives the same bits; this one synchronises least.
  struct Schedule {
    int threads = 0;
    std::vector<std::vector<int>> groups;  ///< per subtree: its tasks in phase order
    std::vector<std::vector<int>> top;     ///< per phase above the subtrees: its tasks
  };
  /// The schedule for @p threads threads (kept until asked for another count).
  const Schedule& schedule(int threads) const;

 private:
  mutable Schedule schedule_;
};

/// L grouped into supernodes: runs of at most kMaxSupernode consecutive columns with the same
/// rows below their diagonal block (in a cloth factor 70-85 % of the nonzeros are in supernodes
/// of 4 or more columns, near the top of the elimination tree). Each supernode stores its row
/// list once and its values as a dense block, row by row, so one load of x_r and of a row
/// index serves w multiply-adds, and both solves read the same single copy of L. Real is the
/// precision of the values and of the solves (double, or float for LinearSolver::kFusedFloat).
template <typename Real>
struct SupernodalFactorT {
  int size = 0;                        ///< n
  std::vector<int> first_column;       ///< per supernode; back() == size
  std::vector<int> row_start;          ///< per supernode, into rows; back() == rows.size()
  /// Rows below each supernode's diagonal block, increasing; after splitSolves the entries
  /// past own_count[s] (rows of another task) hold the task's scratch slot instead.
  std::vector<int> rows;
  /// Per supernode: how many of its rows its own task holds (all of them without a split).
  std::vector<int> own_count;
  /// Per supernode of width w: w x w diagonal block (row-major, only the strictly lower part
  /// is used), then w values per entry of its row list. value_start.back() == values.size().
  std::vector<std::size_t> value_start;
  std::vector<Real> values;
  std::vector<Real> inv_diagonal;      ///< 1 / L_jj
  std::vector<int> permutation;        ///< as LowerFactor::permutation
  SolveTasks tasks;                    ///< empty: one serial pass (no split)
  /// The tasks' slots (kNodeStride values each): the solves' work array, so a factor is solved
  /// by one caller at a time.
  mutable std::vector<Real> scratch;

  int supernodeCount() const { return static_cast<int>(first_column.size()) - 1; }
  /// Bytes one solve (forward + backward) streams from the factor.
  long solveBytes() const {
    return 2 * static_cast<long>(sizeof(Real) * (values.size() + inv_diagonal.size()) +
                                 sizeof(int) * rows.size());
  }
};
using SupernodalFactor = SupernodalFactorT<double>;
using SupernodalFactorF = SupernodalFactorT<float>;

/// Groups @p lower into supernodes of at most @p max_width (<= kMaxSupernode) columns (no split).
SupernodalFactor makeSupernodal(const LowerFactor& lower, int max_width = kMaxSupernode);

/// Leaves of the solves' split: at most 2^kSolveSplitDepth, each with at least kMinSolveTask
/// factor entries (a smaller task costs more in synchronisation than it saves).
constexpr int kSolveSplitDepth = 4;
constexpr long kMinSolveTask = 32768;

/// Splits @p factor's solves into tasks (SolveTasks; solve_partition.cpp) by recursive
/// bisection of its elimination tree: the root's chain of supernodes down to the first branching
/// into subtrees of balanced size is a separator task, the subtrees on either side are split
/// again, until @p max_depth levels or subtrees under 2 @p min_task entries, which become the
/// leaves. A function of the factor only (never of a thread count). A factor whose tree does not
/// branch gets one task.
void splitSolves(SupernodalFactor& factor, int max_depth = kSolveSplitDepth,
                 long min_task = kMinSolveTask);

/// The same factor (structure, split) with its values rounded to float.
SupernodalFactorF toSinglePrecision(const SupernodalFactor& factor);

/// Forward substitution L Z = B in place on @p x (n x kNodeStride values, node k of the
/// factor's order at x[4k]): per supernode, the dense diagonal block, then one update of each
/// row below it with the w solved values held in registers. The tasks of a phase run on up to
/// @p threads threads; the result does not depend on @p threads.
void forwardSolve3(const SupernodalFactor& factor, double* x, int threads = 1);
void forwardSolve3(const SupernodalFactorF& factor, float* x, int threads = 1);

/// Backward substitution L^T X = Z in place; same layout: per supernode (last first), one pass
/// over its rows accumulating w dot products, then its diagonal block.
void backwardSolve3(const SupernodalFactor& factor, double* x, int threads = 1);
void backwardSolve3(const SupernodalFactorF& factor, float* x, int threads = 1);

/// Solves L L^T X = B in place for the three columns together: forward then backward. Reads
/// the factor twice (once per direction) where a column-at-a-time library solve reads it six
/// times. In double the result matches a library solve to round-off (a test checks 1e-12).
template <typename Real>
void solveFused3(const SupernodalFactorT<Real>& factor, Real* x, int threads = 1) {
  forwardSolve3(factor, x, threads);
  backwardSolve3(factor, x, threads);
}

}  // namespace cloth_sim
