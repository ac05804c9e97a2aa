#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

TEST(GridBuilder, SpringCountsPerFamily) {
  GridSpec spec;
  spec.rows = 7;
  spec.cols = 9;
  spec.material.has_bending = true;
  const Model m = buildGrid(spec).model;
  EXPECT_EQ(m.familySize(SpringFamily::kStructural), 7 * 8 + 9 * 6);
  EXPECT_EQ(m.familySize(SpringFamily::kShear), 2 * 6 * 8);
  EXPECT_EQ(m.familySize(SpringFamily::kBending), 7 * 7 + 9 * 5);
  EXPECT_EQ(m.triangles.cols(), 2 * 6 * 8);
  spec.material.has_shear = false;
  spec.material.has_bending = false;
  EXPECT_EQ(buildGrid(spec).model.springs.size(), 7u * 8 + 9 * 6);
}

TEST(GridBuilder, PaperTopologyHas32158SpringsAt81x81) {
  // Liu et al. 2013, Fig. 1: triangle edges plus distance-2 bending springs.
  GridSpec spec;
  spec.rows = spec.cols = 81;
  spec.shear_pattern = ShearPattern::kTriangle;
  spec.material.has_bending = true;
  EXPECT_EQ(buildGrid(spec).model.springs.size(), 32158u);
}

TEST(GridBuilder, LumpedMassesRestLengthsAndPose) {
  GridSpec spec;
  spec.rows = 5;
  spec.cols = 3;
  spec.width = 2.0;
  spec.height = 1.0;
  spec.material.areal_density = 0.3;
  spec.material.has_bending = true;
  spec.pose = Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX());
  const BuiltObject g = buildGrid(spec);
  EXPECT_NEAR(g.model.mass.sum(), 0.3 * 2.0 * 1.0, 1e-12);
  const double cell = 0.3 * 1.0 * 0.25;  // dx = 1, dy = 0.25
  EXPECT_NEAR(g.model.mass[gridVertex(0, 0, 3)], cell / 4, 1e-15);
  EXPECT_NEAR(g.model.mass[gridVertex(0, 1, 3)], cell / 2, 1e-15);
  EXPECT_NEAR(g.model.mass[gridVertex(2, 1, 3)], cell, 1e-15);
  // Row 0 is on top: local y = +0.5 maps to world z = 3 + 0.5 under the +90 deg roll.
  EXPECT_NEAR((g.rest_positions.col(gridVertex(0, 0, 3)) - Vec3(0.0, 2.0, 3.5)).norm(), 0.0, 1e-12);
  for (std::size_t s = 0; s < g.model.springs.size(); ++s) {
    const double r = g.model.springs.rest_length[s];
    switch (g.model.springs.family[s]) {
      case SpringFamily::kStructural: EXPECT_TRUE(std::abs(r - 1.0) < 1e-12 || std::abs(r - 0.25) < 1e-12); break;
      case SpringFamily::kShear: EXPECT_NEAR(r, std::hypot(1.0, 0.25), 1e-12); break;
      case SpringFamily::kBending: EXPECT_TRUE(std::abs(r - 2.0) < 1e-12 || std::abs(r - 0.5) < 1e-12); break;
    }
  }
}

TEST(GridBuilder, TrianglesAllFaceTheSameWay) {
  GridSpec spec;
  spec.rows = 4;
  spec.cols = 5;
  const BuiltObject g = buildGrid(spec);
  for (int t = 0; t < g.model.triangles.cols(); ++t) {
    const Vec3 a = g.rest_positions.col(g.model.triangles(0, t));
    const Vec3 b = g.rest_positions.col(g.model.triangles(1, t));
    const Vec3 c = g.rest_positions.col(g.model.triangles(2, t));
    EXPECT_GT((b - a).cross(c - a).z(), 0.0);
  }
}

TEST(GridBuilder, RefusesBadSpecs) {
  GridSpec spec;
  spec.rows = 1;
  EXPECT_THROW(buildGrid(spec), std::invalid_argument);
  spec.rows = 3;
  spec.width = -1.0;
  EXPECT_THROW(buildGrid(spec), std::invalid_argument);
  spec.width = 1.0;
  spec.material.areal_density = 0.0;
  EXPECT_THROW(buildGrid(spec), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
