#include "test_util.h"

namespace cloth_sim::test {

std::string sourcePath(const std::string& relative) {
  return std::string(CLOTH_SIM_SOURCE_DIR) + "/" + relative;
}

HangingSpring makeHangingSpring(double mass, double stiffness, double rest, double h) {
  HangingSpring out;
  out.model.mass = Eigen::Vector2d(mass, mass);
  out.model.springs.add(0, 1, rest, stiffness, SpringFamily::kStructural);
  out.model.time_step = h;
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
  spec.structural = structural;
  spec.has_shear = shear > 0.0;
  spec.shear = shear;
  spec.has_bending = bending > 0.0;
  spec.bending = bending;
  return buildGrid(spec);
}

SolverSettings convergedSettings(int max_iterations, double tolerance) {
  SolverSettings s;
  s.max_iterations = max_iterations;
  s.tolerance = tolerance;
  return s;
}

}  // namespace cloth_sim::test
