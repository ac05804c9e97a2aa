/// @file supernodal_solves.h
/// Hand-written triangular solves for the global step of local/global (Liu et al. 2013, sec. 4):
/// one scalar factor L, three right-hand sides (x, y, z) solved in the same pass.
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

/// L grouped into supernodes: runs of at most kMaxSupernode consecutive columns with the same
/// rows below their diagonal block (in a cloth factor 70-85 % of the nonzeros are in supernodes
/// of 4 or more columns, near the top of the elimination tree). Each supernode stores its row
/// list once and its values as a dense block, row by row, so one load of x_r and of a row
/// index serves w multiply-adds, and both solves read the same single copy of L.
struct SupernodalFactor {
  int size = 0;                        ///< n
  std::vector<int> first_column;       ///< per supernode; back() == size
  std::vector<int> row_start;          ///< per supernode, into rows; back() == rows.size()
  std::vector<int> rows;               ///< rows below each supernode's diagonal block
  /// Per supernode of width w: w x w diagonal block (row-major, only the strictly lower part
  /// is used), then w values per entry of its row list. value_start.back() == values.size().
  std::vector<std::size_t> value_start;
  std::vector<double> values;
  std::vector<double> inv_diagonal;    ///< 1 / L_jj
  std::vector<int> permutation;        ///< as LowerFactor::permutation

  int supernodeCount() const { return static_cast<int>(first_column.size()) - 1; }
  /// Bytes one solve (forward + backward) streams from the factor.
  long solveBytes() const;
};

/// Groups @p lower into supernodes of at most @p max_width (<= kMaxSupernode) columns.
SupernodalFactor makeSupernodal(const LowerFactor& lower, int max_width = kMaxSupernode);

/// Forward substitution L Z = B in place on @p x (n x kNodeStride doubles, node k of the
/// factor's order at x[4k]): per supernode, the dense diagonal block, then one update of each
/// row below it with the w solved values held in registers.
void forwardSolve3(const SupernodalFactor& factor, double* x);

/// Backward substitution L^T X = Z in place; same layout: per supernode (last first), one pass
/// over its rows accumulating w dot products, then its diagonal block.
void backwardSolve3(const SupernodalFactor& factor, double* x);

/// Solves L L^T X = B in place for the three columns together: forward then backward. Reads
/// the factor twice (once per direction) where a column-at-a-time library solve reads it six
/// times. Result matches a library solve to round-off (a test checks 1e-12).
inline void solveFused3(const SupernodalFactor& factor, double* x) {
  forwardSolve3(factor, x);
  backwardSolve3(factor, x);
}

}  // namespace cloth_sim
