#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(LocalGlobal, HangingMassSettlesAtStaticStretchMgOverK) {
  LocalGlobalSolver solver;
  EXPECT_LT(test::staticStretchError(solver, test::convergedSettings()), 1e-6);
}

TEST(LocalGlobal, SoftPinSagsByWeightOverPinStiffness) {
  LocalGlobalSolver solver;
  EXPECT_LT(test::softPinSagError(solver, test::convergedSettings()), 1e-6);
}

/// A moving 6 x 6 cloth with a hard and a soft pin, a few steps into a swing.
struct SwingingCloth {
  BuiltObject g = test::makeGrid(6, 6, 200.0, 20.0, 2.0);
  PinSet pins;
  State state;
  static constexpr double kH = 1.0 / 60.0;  ///< s, the step
  SwingingCloth() {
    pins.add(0, g.rest_positions.col(0), 0.0, 36);
    pins.add(5, g.rest_positions.col(5), 150.0, 36);
    state = State::atRest(g.rest_positions);
    LocalGlobalSolver warmup;
    for (int k = 0; k < 15; ++k) warmup.step({g.model, pins, kH, 1}, SolverSettings{}, state);
  }
  SolverInput input() const { return {g.model, pins, kH, 1}; }
};

/// Relative position error |x - x*| / |y - x*| of @p solver run to convergence on the step of
/// @p c, against Newton's converged solution x* of the same step (y: the initial guess).
double convergedErrorAgainstNewton(Solver& solver, const SwingingCloth& c) {
  State reference = c.state;
  NewtonSolver newton;
  EXPECT_TRUE(newton.step(c.input(), test::convergedSettings(1000, 1e-14), reference).converged);
  const Points y = ImplicitStepProblem::build(c.g.model, c.pins, c.state, c.kH).inertial;
  State s = c.state;
  EXPECT_TRUE(solver.step(c.input(), test::convergedSettings(100000, 1e-14), s).converged);
  return (s.positions - reference.positions).norm() / (y - reference.positions).norm();
}

TEST(LocalGlobal, ConvergesToNewtonsSolutionOfTheSameStep) {
  LocalGlobalSolver lg;
  EXPECT_LT(convergedErrorAgainstNewton(lg, SwingingCloth()), 1e-8);
}

TEST(LocalGlobal, ObjectiveNeverIncreasesAcrossIterations) {
  SwingingCloth c;
  // Squash the start so many springs are compressed: the interesting case for monotonicity.
  c.state.positions = 0.7 * c.state.positions;
  c.pins.moveTarget(0, c.state.positions.col(0));
  std::vector<double> trace;
  LocalGlobalSolver lg;
  lg.setObjectiveTrace(&trace);
  State s = c.state;
  lg.step(c.input(), test::convergedSettings(300, 0.0), s);
  ASSERT_EQ(trace.size(), 301u);
  for (std::size_t k = 1; k < trace.size(); ++k) {
    EXPECT_LE(trace[k], trace[k - 1] + 1e-12 * std::abs(trace[k - 1])) << "iteration " << k;
  }
  EXPECT_LT(trace.back(), trace.front());
}

TEST(LocalGlobal, ConservesLinearMomentumAtEveryIterationCount) {
  LocalGlobalSolver solver;
  // Not converged: each global solve conserves momentum on its own (round-off only).
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(3, 0.0), 50), 1e-9);
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(1, 0.0), 50), 1e-9);
}

TEST(LocalGlobal, FactorKeptAcrossStepsAndTargetMoves) {
  SwingingCloth c;
  LocalGlobalSolver lg;
  State s = c.state;
  for (int k = 0; k < 30; ++k) {
    c.pins.moveTarget(c.pins.pins()[0].id, c.g.rest_positions.col(0) + Vec3(0.01 * k, 0, 0));
    lg.step({c.g.model, c.pins, c.kH, 7}, SolverSettings{}, s);
  }
  EXPECT_EQ(lg.factorizationCount(), 1);
  lg.step({c.g.model, c.pins, c.kH, 8}, SolverSettings{}, s);  // a new revision: refactor once
  lg.step({c.g.model, c.pins, c.kH, 8}, SolverSettings{}, s);
  EXPECT_EQ(lg.factorizationCount(), 2);
}

TEST(LocalGlobal, EveryLinearSolverGivesTheSameTrajectory) {
  // The hand-written kernels and the two libraries differ in speed only.
  SwingingCloth c;
  std::vector<Points> results;
  for (LinearSolver backend : {LinearSolver::kFused, LinearSolver::kCholmod, LinearSolver::kEigen}) {
    LocalGlobalSolver lg;
    SolverSettings settings;
    settings.linear_solver = backend;
    State s = c.state;
    for (int k = 0; k < 20; ++k) lg.step(c.input(), settings, s);
    results.push_back(s.positions);
  }
  EXPECT_LT((results[1] - results[0]).norm(), 1e-11 * results[0].norm());
  EXPECT_LT((results[2] - results[0]).norm(), 1e-11 * results[0].norm());
}

TEST(LocalGlobal, SwitchingLinearSolverRefactorsOnce) {
  SwingingCloth c;
  LocalGlobalSolver lg;
  SolverSettings settings;
  State s = c.state;
  lg.step(c.input(), settings, s);
  settings.linear_solver = LinearSolver::kEigen;
  lg.step(c.input(), settings, s);
  lg.step(c.input(), settings, s);
  EXPECT_EQ(lg.factorizationCount(), 2);
}

TEST(LocalGlobal, ObserverSeesEveryIterateAndTheLastIsTheResult) {
  SwingingCloth c;
  for (bool chebyshev : {false, true}) {
    std::unique_ptr<LocalGlobalSolver> solver;
    if (chebyshev) solver = std::make_unique<ChebyshevSolver>();
    else solver = std::make_unique<LocalGlobalSolver>();
    State s = c.state;
    solver->step(c.input(), SolverSettings{}, s);  // chebyshev: measures rho first
    std::vector<int> seen;
    Points last;
    solver->setIterateObserver([&](int k, const Points& x) {
      seen.push_back(k);
      last = x;
      return true;
    });
    s = c.state;
    solver->step(c.input(), test::convergedSettings(12, 0.0), s);
    // k counts solves; a chebyshev restart spends two solves between two observations.
    ASSERT_FALSE(seen.empty());
    if (!chebyshev) {
      ASSERT_EQ(seen.size(), 12u);
    }
    for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_GT(seen[k], seen[k - 1]);
    EXPECT_EQ(seen.back(), 12) << solver->name();
    EXPECT_EQ(last, s.positions) << solver->name();
    // Returning false stops the step at that iterate.
    seen.clear();
    solver->setIterateObserver([&](int k, const Points& x) {
      seen.push_back(k);
      last = x;
      return k < 5;
    });
    s = c.state;
    const SolveResult r = solver->step(c.input(), test::convergedSettings(12, 0.0), s);
    EXPECT_GE(seen.back(), 5) << solver->name();
    EXPECT_LE(seen.back(), 6) << solver->name();
    EXPECT_EQ(r.iterations, seen.back()) << solver->name();
    EXPECT_EQ(last, s.positions) << solver->name();
  }
}

TEST(LocalGlobal, WarmStartNeverStartsWorseAndConvergesToTheSameSolution) {
  SwingingCloth c;
  for (bool chebyshev : {false, true}) {
    std::unique_ptr<LocalGlobalSolver> cold, warm;
    if (chebyshev) {
      cold = std::make_unique<ChebyshevSolver>();
      warm = std::make_unique<ChebyshevSolver>();
    } else {
      cold = std::make_unique<LocalGlobalSolver>();
      warm = std::make_unique<LocalGlobalSolver>();
    }
    SolverSettings settings = test::convergedSettings(5, 0.0);
    State b = c.state;
    std::vector<double> cold_trace, warm_trace;
    cold->setObjectiveTrace(&cold_trace);
    warm->setObjectiveTrace(&warm_trace);
    for (int k = 0; k < 20; ++k) {
      settings.warm_start = false;
      State from = b;  // both step from the same state: the warm solver's
      cold->step(c.input(), settings, from);
      settings.warm_start = true;
      warm->step(c.input(), settings, b);
      EXPECT_LE(warm_trace.front(), cold_trace.front()) << "step " << k;  // g(x_0) <= g(y)
    }
    // Run to convergence: the start changes the path, not the solution.
    State from = b;
    settings = test::convergedSettings(100000, 1e-14);
    cold->step(c.input(), settings, from);
    settings.warm_start = true;
    warm->step(c.input(), settings, b);
    EXPECT_LT((b.positions - from.positions).norm(), 1e-9 * b.positions.norm()) << warm->name();
  }
}

TEST(Chebyshev, ConvergesToNewtonsSolution) {
  SwingingCloth c;
  ChebyshevSolver cheb;
  State warm = c.state;
  cheb.step(c.input(), SolverSettings{}, warm);  // the first step measures rho
  EXPECT_LT(convergedErrorAgainstNewton(cheb, c), 1e-8);
}

TEST(Chebyshev, NeverWorseThanPlainLocalGlobalAndMonotone) {
  SwingingCloth c;
  c.g.model.setFamilyStiffness(SpringFamily::kStructural, 5000.0);  // slow plain convergence
  ChebyshevSolver cheb;
  LocalGlobalSolver plain;
  std::vector<double> cheb_trace, plain_trace;
  cheb.setObjectiveTrace(&cheb_trace);
  plain.setObjectiveTrace(&plain_trace);
  State warm = c.state;
  cheb.step(c.input(), SolverSettings{}, warm);  // first step measures rho
  EXPECT_GT(cheb.rho(), 0.5);
  EXPECT_LT(cheb.rho(), 1.0);
  for (int iterations : {1, 2, 3, 5, 10, 20, 50, 100}) {
    State a = c.state, b = c.state;
    cheb.step(c.input(), test::convergedSettings(iterations, 0.0), a);
    plain.step(c.input(), test::convergedSettings(iterations, 0.0), b);
    EXPECT_LE(cheb_trace.back(), plain_trace.back() + 1e-12 * std::abs(plain_trace.back()))
        << iterations << " iterations";
    for (std::size_t k = 1; k < cheb_trace.size(); ++k) {
      EXPECT_LE(cheb_trace[k], cheb_trace[k - 1] + 1e-12 * std::abs(cheb_trace[k - 1]));
    }
  }
}

TEST(Anderson, ConvergesToNewtonsSolution) {
  AndersonSolver anderson;
  EXPECT_LT(convergedErrorAgainstNewton(anderson, SwingingCloth()), 1e-8);
}

TEST(Anderson, AcceptedIteratesMonotoneAndNeverWorseThanPlainLocalGlobal) {
  SwingingCloth c;
  c.g.model.setFamilyStiffness(SpringFamily::kStructural, 5000.0);  // slow plain convergence
  c.state.positions = 0.7 * c.state.positions;  // compressed springs: the safeguard has work
  c.pins.moveTarget(0, c.state.positions.col(0));
  AndersonSolver anderson;
  LocalGlobalSolver plain;
  std::vector<double> anderson_trace, plain_trace;
  anderson.setObjectiveTrace(&anderson_trace);
  plain.setObjectiveTrace(&plain_trace);
  for (int iterations : {1, 2, 3, 5, 10, 20, 50, 100}) {
    State a = c.state, b = c.state;
    anderson.step(c.input(), test::convergedSettings(iterations, 0.0), a);
    plain.step(c.input(), test::convergedSettings(iterations, 0.0), b);
    EXPECT_LE(anderson_trace.back(), plain_trace.back() + 1e-12 * std::abs(plain_trace.back()))
        << iterations << " iterations";
    for (std::size_t k = 1; k < anderson_trace.size(); ++k) {
      EXPECT_LE(anderson_trace[k], anderson_trace[k - 1] + 1e-12 * std::abs(anderson_trace[k - 1]))
          << iterations << " iterations, iterate " << k;
    }
  }
  EXPECT_GT(anderson.rejections(), 0);  // the safeguard was exercised
}

TEST(Anderson, WindowOfOneStillConvergesAndWindowIsValidated) {
  AndersonSolver anderson;
  SwingingCloth c;
  State s = c.state;
  SolverSettings settings = test::convergedSettings(100000, 1e-12);
  settings.params.set(settings::kAndersonWindow, 1);
  EXPECT_TRUE(anderson.step(c.input(), settings, s).converged);
  settings.params.set(settings::kAndersonWindow, 0);
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  settings.params.set(settings::kAndersonWindow, 51);
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  EXPECT_STREQ(makeSolver("anderson")->name(), "anderson");
}

TEST(Lbfgs, GradientMatchesFiniteDifferencesOfTheObjective) {
  SwingingCloth c;  // a hard and a soft pin, springs stretched and compressed
  LocalGlobalProblem probe;
  probe.begin(c.input(), SolverSettings{}, c.state);
  NodeBuffer x = probe.inertial();
  std::srand(3);
  for (int k = 0; k < probe.freeNodeCount(); ++k)
    for (int d = 0; d < 3; ++d) x[kNodeStride * k + d] += 0.02 * (std::rand() / double(RAND_MAX) - 0.5);
  NodeBuffer gradient;
  const double g = probe.objectiveAndGradient(x, gradient);
  EXPECT_NEAR(g, probe.objectiveAt(x), 1e-12 * std::abs(g));
  ASSERT_EQ(gradient.size(), x.size());
  double worst = 0.0, scale = 0.0;
  const double eps = 1e-6;
  for (int k = 0; k < probe.freeNodeCount(); ++k) {
    for (int d = 0; d < 3; ++d) {
      NodeBuffer plus = x, minus = x;
      plus[kNodeStride * k + d] += eps;
      minus[kNodeStride * k + d] -= eps;
      const double fd = (probe.objectiveAt(plus) - probe.objectiveAt(minus)) / (2 * eps);
      worst = std::max(worst, std::abs(fd - gradient[kNodeStride * k + d]));
      scale = std::max(scale, std::abs(fd));
    }
    EXPECT_EQ(gradient[kNodeStride * k + 3], 0.0);
  }
  EXPECT_GT(scale, 0.0);
  EXPECT_LT(worst, 1e-6 * scale);
  for (std::size_t i = kNodeStride * probe.freeNodeCount(); i < gradient.size(); ++i)
    EXPECT_EQ(gradient[i], 0.0);  // hard-pinned rows
}

TEST(Lbfgs, ConvergesToNewtonsSolution) {
  LbfgsSolver lbfgs;
  EXPECT_LT(convergedErrorAgainstNewton(lbfgs, SwingingCloth()), 1e-8);
}

TEST(Lbfgs, FirstIterationIsTheLocalGlobalIterate) {
  SwingingCloth c;
  LbfgsSolver lbfgs;
  LocalGlobalSolver plain;
  State a = c.state, b = c.state;
  lbfgs.step(c.input(), test::convergedSettings(1, 0.0), a);
  plain.step(c.input(), test::convergedSettings(1, 0.0), b);
  EXPECT_LT((a.positions - b.positions).norm(), 1e-12 * b.positions.norm());
}

TEST(Lbfgs, AcceptedIteratesMonotoneAndNeverWorseThanPlainLocalGlobal) {
  SwingingCloth c;  // anderson's hard case
  c.g.model.setFamilyStiffness(SpringFamily::kStructural, 5000.0);  // slow plain convergence
  c.state.positions = 0.7 * c.state.positions;  // compressed springs: non-convex g
  c.pins.moveTarget(0, c.state.positions.col(0));
  LbfgsSolver lbfgs;
  LocalGlobalSolver plain;
  std::vector<double> lbfgs_trace, plain_trace;
  lbfgs.setObjectiveTrace(&lbfgs_trace);
  plain.setObjectiveTrace(&plain_trace);
  for (int iterations = 1; iterations <= 100; ++iterations) {
    State a = c.state, b = c.state;
    lbfgs.step(c.input(), test::convergedSettings(iterations, 0.0), a);
    plain.step(c.input(), test::convergedSettings(iterations, 0.0), b);
    EXPECT_LE(lbfgs_trace.back(), plain_trace.back() + 1e-12 * std::abs(plain_trace.back()))
        << iterations << " iterations";
    for (std::size_t k = 1; k < lbfgs_trace.size(); ++k) {
      EXPECT_LE(lbfgs_trace[k], lbfgs_trace[k - 1] + 1e-12 * std::abs(lbfgs_trace[k - 1]))
          << iterations << " iterations, iterate " << k;
    }
  }
}

TEST(Lbfgs, ConservesLinearMomentum) {
  LbfgsSolver solver;
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(3, 0.0), 50), 1e-9);
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(10, 0.0), 50), 1e-9);
}

TEST(Lbfgs, ObserverSeesTheResultAndWindowIsValidated) {
  SwingingCloth c;
  LbfgsSolver lbfgs;
  int last_k = 0;
  Points last;
  lbfgs.setIterateObserver([&](int k, const Points& x) {
    EXPECT_GT(k, last_k);
    last_k = k;
    last = x;
    return true;
  });
  State s = c.state;
  const SolveResult r = lbfgs.step(c.input(), test::convergedSettings(12, 0.0), s);
  EXPECT_EQ(r.iterations, 12);
  EXPECT_EQ(last_k, 12);
  EXPECT_EQ(last, s.positions);
  EXPECT_FALSE(r.used_contacts);

  lbfgs.setIterateObserver({});
  SolverSettings settings = test::convergedSettings(100000, 1e-12);
  settings.params.set(settings::kLbfgsWindow, 1);
  s = c.state;
  EXPECT_TRUE(lbfgs.step(c.input(), settings, s).converged);
  settings.params.set(settings::kLbfgsWindow, 0);
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  settings.params.set(settings::kLbfgsWindow, 51);
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  EXPECT_STREQ(makeSolver("lbfgs")->name(), "lbfgs");
}

}  // namespace
}  // namespace cloth_sim
