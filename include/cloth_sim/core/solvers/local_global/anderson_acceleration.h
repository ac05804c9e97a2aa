/// @file anderson_acceleration.h
/// Peng, Deng, Zhang, Liu 2018, "Anderson Acceleration for Geometry Optimization and Physics
/// Simulation", ACM TOG 37(4), Algorithm 2.
#pragma once

#include <Eigen/Core>

#include "cloth_sim/core/solvers/local_global/local_global_driver.h"

namespace cloth_sim {

namespace settings {
/// anderson: number m of past iterates whose differences form the least-squares model (Peng et
/// al. 2018 use 5-10).
inline constexpr SolverParam kAndersonWindow{
    {"solver.anderson.window", "", Range::closed(1, 50), true, "", "",
     "Past iterates in Anderson's least-squares model", 0},
    5};
}  // namespace settings

/// Anderson extrapolation of the local/global fixed-point map G: with residuals
/// F_j = G(x_j) - x_j and the last m differences dF_j = F_{j+1} - F_j, dG_j = G(x_{j+1}) - G(x_j)
/// (m = settings::kAndersonWindow):
///   theta = argmin |F_k - dF theta|_2,   x_{k+1} = G(x_k) - dG theta.
/// A restart (the driver's safeguard) clears the history. Per iteration it adds O(m n) vector
/// work (n = 4 N doubles) to the local/global iteration.
class AndersonAcceleration final : public Acceleration {
 public:
  void begin(const SolverInput& input, const SolverSettings& settings) override;
  void restart() override;
  bool extrapolate(const NodeBuffer& x_prev, const NodeBuffer& x, const NodeBuffer& x_hat,
                   NodeBuffer& x_next) override;
  /// Restarts (iterates rejected by the safeguard) since construction.
  int restarts() const { return restarts_; }

 private:
  void clearHistory();

  int window_ = 5;
  Eigen::MatrixXd d_f_, d_g_;  ///< columns: the last differences of F and G (a ring)
  Eigen::MatrixXd gram_;       ///< dF^T dF of the columns in use
  int history_ = 0;            ///< columns in use
  int next_column_ = 0;        ///< the ring's next column to overwrite
  NodeBuffer f_last_, g_last_;  ///< F and G of the previous accepted iterate
  bool has_last_ = false;
  int restarts_ = 0;
  int threads_ = 1;  ///< SolverSettings::threads, resolved (the vector loops' blocks are fixed)
};

}  // namespace cloth_sim
