#include "test_util.h"

#include <cmath>

namespace cloth_sim::test {

std::string sourcePath(const std::string& relative) {
  return std::string(CLOTH_SIM_SOURCE_DIR) + "/" + relative;
}

HangingSpring makeHangingSpring(double mass, double stiffness, double rest, double h) {
  HangingSpring out;
  out.model.mass = Eigen::Vector2d(mass, mass);
  out.model.springs.add(0, 1, rest, stiffness, SpringFamily::kStructural);
  out.h = h;
  out.rest.resize(3, 2);
  out.rest.col(0) = Vec3::Zero();
  out.rest.col(1) = Vec3(0.0, 0.0, -rest);
  out.pins.add(0, Vec3::Zero(), 0.0, 2);
  return out;
}

BuiltObject makeGrid(int rows, int cols, double structural, double shear, double bending) {
  GridSpec spec;
  spec.rows = rows;
  spec.cols = cols;
  spec.pose = Eigen::Translation3d(0.0, 0.0, 1.0) * Eigen::Isometry3d::Identity();
  spec.material.structural = structural;
  spec.material.has_shear = shear > 0.0;
  spec.material.shear = shear;
  spec.material.has_bending = bending > 0.0;
  spec.material.bending = bending;
  return buildGrid(spec);
}

double staticStretchError(Solver& solver, const SolverSettings& settings) {
  const double m = 0.2, k = 50.0, rest = 0.5;
  HangingSpring sys = makeHangingSpring(m, k, rest, 1.0 / 60.0);
  sys.model.damping = 5.0;
  State s = State::atRest(sys.rest);
  for (int step = 0; step < 1200; ++step) solver.step({sys.model, sys.pins, sys.h, 1}, settings, s);
  const double stretch = (s.positions.col(1) - s.positions.col(0)).norm() - rest;
  return std::abs(stretch - m * 9.81 / k) / (m * 9.81 / k);
}

double softPinSagError(Solver& solver, const SolverSettings& settings) {
  const double m = 0.4, k_pin = 80.0;
  Model model;
  model.mass = Eigen::VectorXd::Constant(1, m);
  model.damping = 5.0;
  PinSet pins;
  pins.add(0, Vec3(0, 0, 1), k_pin, 1);
  State s = State::atRest(Points(Vec3(0, 0, 1)));
  for (int step = 0; step < 1200; ++step) solver.step({model, pins, 1.0 / 60.0, 1}, settings, s);
  return std::abs((1.0 - s.positions(2, 0)) - m * 9.81 / k_pin) / (m * 9.81 / k_pin);
}

double momentumDrift(Solver& solver, const SolverSettings& settings, int steps) {
  BuiltObject g = makeGrid(5, 5, 300.0, 30.0, 3.0);
  g.model.gravity.setZero();
  PinSet pins;
  State s = State::atRest(g.rest_positions);
  s.velocities = Points::Random(3, 25);
  const Vec3 p0 = s.velocities * g.model.mass;
  for (int step = 0; step < steps; ++step) solver.step({g.model, pins, 1.0 / 60.0, 1}, settings, s);
  return (s.velocities * g.model.mass - p0).norm() / s.velocities.colwise().norm().dot(g.model.mass);
}

Eigen::SparseMatrix<double> gridSystemMatrix(int rows, int cols, double h) {
  const BuiltObject g = makeGrid(rows, cols, 400.0, 40.0, 4.0);
  const int n = g.model.particleCount();
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, g.model.mass[i]);
  const Springs& s = g.model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double w = h * h * s.stiffness[k];
    entries.emplace_back(s.first[k], s.first[k], w);
    entries.emplace_back(s.second[k], s.second[k], w);
    entries.emplace_back(s.first[k], s.second[k], -w);
    entries.emplace_back(s.second[k], s.first[k], -w);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  return a;
}

Eigen::MatrixXd denseLower(const LowerFactor& f) {
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(f.size, f.size);
  for (int j = 0; j < f.size; ++j) {
    l(j, j) = 1.0 / f.inv_diagonal[j];
    for (int k = f.col_start[j]; k < f.col_start[j + 1]; ++k) l(f.col_row[k], j) = f.col_value[k];
  }
  return l;
}

SolverSettings convergedSettings(int max_iterations, double tolerance) {
  SolverSettings s;
  s.max_iterations = max_iterations;
  s.tolerance = tolerance;
  return s;
}

Simulation makePeerCloth8(Integrator integrator, int iterations) {
  GridSpec spec;
  spec.rows = spec.cols = 8;
  spec.material.areal_density = 1.0;
  spec.shear_pattern = ShearPattern::kTriangle;
  BuiltObject g = buildGrid(spec);
  PinSet pins;
  pins.add(0, g.rest_positions.col(0), 0.0, 64);
  pins.add(7, g.rest_positions.col(7), 0.0, 64);
  SimulationOptions options;
  options.frame_time = 1.0 / 60.0;
  options.settings.integrator = integrator;
  options.settings.substeps = 16;
  options.settings.max_iterations = iterations;
  return Simulation(g.model, g.rest_positions, pins, Colliders(), options);
}

}  // namespace cloth_sim::test
