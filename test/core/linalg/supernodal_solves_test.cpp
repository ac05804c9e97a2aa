#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/linalg/supernodal_solves.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

LowerFactor factorOf(const Eigen::SparseMatrix<double>& a) {
  CholmodFactor factor;
  EXPECT_TRUE(factor.compute(a));
  return factor.exportLower();
}

NodeBuffer toNodes(const Eigen::MatrixX3d& b) {
  NodeBuffer x(kNodeStride * b.rows(), 0.0);
  for (int k = 0; k < b.rows(); ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = b(k, c);
  return x;
}

double distance(const NodeBuffer& x, const Eigen::MatrixX3d& expected) {
  double sum = 0.0;
  for (int k = 0; k < expected.rows(); ++k) {
    for (int c = 0; c < 3; ++c) sum += std::pow(x[kNodeStride * k + c] - expected(k, c), 2);
    EXPECT_EQ(x[kNodeStride * k + 3], 0.0);  // the pad slot stays 0
  }
  return std::sqrt(sum);
}

TEST(TriangularKernels, SupernodesCoverEveryColumnAndKeepEveryEntry) {
  const LowerFactor l = factorOf(test::gridSystemMatrix(23, 17, 1.0 / 30.0));
  for (int width : {1, 3, kMaxSupernode}) {
    const SupernodalFactor f = makeSupernodal(l, width);
    ASSERT_EQ(f.first_column.front(), 0);
    ASSERT_EQ(f.first_column.back(), l.size);
    std::size_t stored = 0;
    for (int s = 0; s < f.supernodeCount(); ++s) {
      const int w = f.first_column[s + 1] - f.first_column[s];
      ASSERT_GE(w, 1);
      ASSERT_LE(w, width);
      stored += w * (w - 1) / 2 + static_cast<std::size_t>(w) * (f.row_start[s + 1] - f.row_start[s]);
    }
    EXPECT_EQ(stored, static_cast<std::size_t>(l.offDiagonalCount())) << "width " << width;
    if (width == kMaxSupernode) {
      EXPECT_LT(f.supernodeCount(), 0.6 * l.size);  // columns do group
    }
  }
}

TEST(TriangularKernels, FusedSolveMatchesALibrarySolveForAllThreeColumns) {
  // Large enough for every supernode width and the remainder loops.
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(23, 17, 1.0 / 30.0);
  const LowerFactor l = factorOf(a);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(a.rows(), 3);
  const Eigen::MatrixX3d solution = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(a).solve(b);
  Eigen::MatrixX3d permuted_b(a.rows(), 3), expected(a.rows(), 3);
  for (int k = 0; k < l.size; ++k) {
    permuted_b.row(k) = b.row(l.permutation[k]);
    expected.row(k) = solution.row(l.permutation[k]);
  }
  for (int width : {1, 2, 5, kMaxSupernode}) {
    NodeBuffer x = toNodes(permuted_b);
    solveFused3(makeSupernodal(l, width), x.data());
    EXPECT_LT(distance(x, expected), 1e-12 * expected.norm()) << "width " << width;
  }
}

TEST(TriangularKernels, ForwardAndBackwardAreTheTwoTriangularSolves) {
  const LowerFactor l = factorOf(test::gridSystemMatrix(9, 8, 1.0 / 60.0));
  const SupernodalFactor f = makeSupernodal(l);
  const Eigen::MatrixXd dense = test::denseLower(l);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(l.size, 3);
  NodeBuffer x = toNodes(b);
  forwardSolve3(f, x.data());
  const Eigen::MatrixX3d z = dense.triangularView<Eigen::Lower>().solve(b);
  EXPECT_LT(distance(x, z), 1e-12 * z.norm());
  backwardSolve3(f, x.data());
  const Eigen::MatrixX3d y = dense.transpose().triangularView<Eigen::Upper>().solve(z);
  EXPECT_LT(distance(x, y), 1e-12 * y.norm());
}

/// The fused solve of @p f on @p b (one row per column of the factor's order), at @p threads.
template <typename Real>
std::vector<Real> solved(const SupernodalFactorT<Real>& f, const Eigen::MatrixX3d& b, int threads) {
  std::vector<Real> x(kNodeStride * b.rows(), Real(0));
  for (int k = 0; k < b.rows(); ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = static_cast<Real>(b(k, c));
  solveFused3(f, x.data(), threads);
  return x;
}

struct SplitCase {
  Eigen::SparseMatrix<double> a;
  LowerFactor lower;
  SupernodalFactor split;
  Eigen::MatrixX3d b, expected;  // in the factor's order
};

/// A grid large enough to split into several levels of tasks.
SplitCase splitCase(int side) {
  SplitCase c;
  c.a = test::gridSystemMatrix(side, side, 1.0 / 60.0);
  c.lower = factorOf(c.a);
  c.split = makeSupernodal(c.lower);
  splitSolves(c.split, kSolveSplitDepth, 2000);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(c.a.rows(), 3);
  const Eigen::MatrixX3d solution = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(c.a).solve(b);
  c.b.resize(c.a.rows(), 3);
  c.expected.resize(c.a.rows(), 3);
  for (int k = 0; k < c.lower.size; ++k) {
    c.b.row(k) = b.row(c.lower.permutation[k]);
    c.expected.row(k) = solution.row(c.lower.permutation[k]);
  }
  return c;
}

TEST(TriangularKernels, SplitCoversEverySupernodeOnceAndAncestorsComeLater) {
  const SplitCase c = splitCase(40);
  const SolveTasks& tasks = c.split.tasks;
  ASSERT_GE(tasks.tasks.size(), 7u) << "a 40 x 40 grid splits into several levels";
  std::vector<int> task_of(c.split.supernodeCount(), -1);
  for (std::size_t t = 0; t < tasks.tasks.size(); ++t) {
    for (int s : tasks.tasks[t].supernodes) {
      ASSERT_EQ(task_of[s], -1) << "supernode " << s << " in two tasks";
      task_of[s] = static_cast<int>(t);
    }
    const int parent = tasks.tasks[t].parent;
    if (parent >= 0) EXPECT_GT(parent, static_cast<int>(t)) << "a separator runs after its subtrees";
  }
  for (int s = 0; s < c.split.supernodeCount(); ++s) ASSERT_GE(task_of[s], 0) << s;
  // The leaves hold most of the work, and the part no two threads can share (the separator
  // above everything) is small.
  long leaves = 0, root = 0, all = 0;
  for (const SolveTasks::Task& t : tasks.tasks) {
    for (int s : t.supernodes) {
      const long w = c.split.value_start[s + 1] - c.split.value_start[s];
      all += w;
      if (t.leaf) leaves += w;
      if (t.parent < 0) root += w;
    }
  }
  EXPECT_GT(leaves, 0.5 * all);
  EXPECT_LT(root, 0.15 * all);
}

TEST(TriangularKernels, SplitSolveMatchesALibrarySolveWithTheSameBitsOnAnyThreads) {
  const SplitCase c = splitCase(40);
  const std::vector<double> one = solved(c.split, c.b, 1);
  NodeBuffer x(one.begin(), one.end());
  EXPECT_LT(distance(x, c.expected), 1e-12 * c.expected.norm());
  for (int threads : {2, 3, 4, 16}) EXPECT_EQ(solved(c.split, c.b, threads), one) << threads;
  // And the same bits whatever ran before (the scratch slots are rewritten by every solve).
  EXPECT_EQ(solved(c.split, c.b, 2), one);
}

TEST(TriangularKernels, SinglePrecisionSolveIsCloseAndThreadIndependent) {
  const SplitCase c = splitCase(40);
  const SupernodalFactorF single = toSinglePrecision(c.split);
  const std::vector<float> one = solved(single, c.b, 1);
  NodeBuffer x(one.begin(), one.end());
  // Float: the factor's rounding amplified by the condition number (small at h = 1/60 s).
  EXPECT_LT(distance(x, c.expected), 1e-5 * c.expected.norm());
  EXPECT_GT(distance(x, c.expected), 1e-12 * c.expected.norm());  // it is float
  for (int threads : {2, 3}) EXPECT_EQ(solved(single, c.b, threads), one) << threads;
}

TEST(TriangularKernels, ASmallFactorIsNotSplit) {
  SupernodalFactor f = makeSupernodal(factorOf(test::gridSystemMatrix(6, 6, 1.0 / 60.0)));
  splitSolves(f);
  EXPECT_TRUE(f.tasks.tasks.empty());
}

}  // namespace
}  // namespace cloth_sim
