// buildMarkers: layers, stable ids, DELETE only for what is gone, no non-finite number ever.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/node/marker_builder.h"

namespace cloth_sim::node {
namespace {

using visualization_msgs::Marker;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A 3 x 4 grid with two pins, two spheres and a ground.
class MarkerBuilderTest : public ::testing::Test {
 protected:
  MarkerBuilderTest() {
    GridSpec spec;
    spec.rows = 3;
    spec.cols = 4;
    BuiltObject grid = buildGrid(spec);
    positions_ = grid.rest_positions;
    triangles_ = grid.model.triangles;
    strain_ = Eigen::VectorXd::Zero(positions_.cols());
    pins_ = {makePin(0, 0), makePin(4, 3)};
    pins_[1].stiffness = 20.0;
    spheres_ = {makeSphere(1, Vec3(0, 0, -0.5), 0.2), makeSphere(6, Vec3(1, 0, 0), 0.1)};
    ground_.enabled = true;
    ground_.height = -1.0;
    header_.frame_id = "world";
    header_.stamp = ros::Time(3, 0);
  }

  Pin makePin(int id, int vertex) const {
    Pin p;
    p.id = id;
    p.vertex = vertex;
    p.target = positions_.col(vertex);
    return p;
  }
  static SphereCollider makeSphere(int id, const Vec3& c, double r) {
    SphereCollider s;
    s.id = id;
    s.center = c;
    s.radius = r;
    return s;
  }
  MarkerBuild build(const ShownMarkers& before = {}) const {
    const MarkerScene scene{positions_, triangles_, strain_, pins_, spheres_, ground_,
                            Vec3(0, 0, 0), 4.0};
    return buildMarkers(scene, style_, header_, before);
  }
  static std::vector<const Marker*> find(const MarkerBuild& b, const std::string& ns) {
    std::vector<const Marker*> out;
    for (const Marker& m : b.markers.markers) {
      if (m.ns == ns) out.push_back(&m);
    }
    return out;
  }

  Points positions_;
  Eigen::Matrix3Xi triangles_;
  Eigen::VectorXd strain_;
  std::vector<Pin> pins_;
  std::vector<SphereCollider> spheres_;
  GroundPlane ground_;
  MarkerStyle style_;
  std_msgs::Header header_;
};

TEST_F(MarkerBuilderTest, TheClothIsOneTriangleListWithAColourPerPoint) {
  const MarkerBuild b = build();
  const auto cloth = find(b, names::kClothNs);
  ASSERT_EQ(cloth.size(), 1u);
  const Marker& m = *cloth[0];
  EXPECT_EQ(m.id, 0);
  EXPECT_EQ(m.type, Marker::TRIANGLE_LIST);
  EXPECT_EQ(m.action, Marker::ADD);
  EXPECT_EQ(m.header.frame_id, "world");
  EXPECT_EQ(m.header.stamp, ros::Time(3, 0));
  EXPECT_EQ(m.pose.orientation.w, 1.0);
  EXPECT_EQ(m.scale.x, 1.0);
  ASSERT_EQ(m.points.size(), 3u * 2 * 2 * 3);  // two triangles per quad, 2 x 3 quads
  ASSERT_EQ(m.colors.size(), m.points.size());
  for (Eigen::Index t = 0; t < triangles_.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const geometry_msgs::Point& p = m.points[3 * t + k];
      const Vec3 expected = positions_.col(triangles_(k, t));
      EXPECT_EQ(Vec3(p.x, p.y, p.z), expected);
    }
  }
  EXPECT_EQ(b.sanitized, 0);
}

TEST_F(MarkerBuilderTest, PinsSpheresAndGroundHaveStableIdsAndSizes) {
  const MarkerBuild b = build();
  const auto pins = find(b, names::kPinsNs);
  ASSERT_EQ(pins.size(), 2u);
  EXPECT_EQ(pins[0]->id, 0);
  EXPECT_EQ(pins[1]->id, 4);
  EXPECT_EQ(pins[1]->type, Marker::SPHERE);
  EXPECT_EQ(pins[1]->pose.position.x, positions_(0, 3));
  EXPECT_EQ(pins[1]->scale.x, style_.pin_diameter);
  EXPECT_NE(pins[0]->color.g, pins[1]->color.g);  // hard and soft pins differ

  const auto spheres = find(b, names::kSpheresNs);
  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_EQ(spheres[0]->id, 1);
  EXPECT_EQ(spheres[1]->id, 6);
  EXPECT_EQ(spheres[0]->pose.position.z, -0.5);
  EXPECT_DOUBLE_EQ(spheres[0]->scale.x, 0.4);  // a diameter

  const auto ground = find(b, names::kGroundNs);
  ASSERT_EQ(ground.size(), 1u);
  EXPECT_EQ(ground[0]->type, Marker::CUBE);
  // Its top face just under the plane (a cloth lying on it must not flicker through it).
  EXPECT_DOUBLE_EQ(ground[0]->pose.position.z + 0.5 * ground[0]->scale.z, -1.0 - kGroundDrawGap);
  EXPECT_GT(kGroundDrawGap, 0.0);
  EXPECT_LT(kGroundDrawGap, 0.005);
  EXPECT_EQ(ground[0]->scale.x, 4.0);

  for (const Marker& m : b.markers.markers) EXPECT_EQ(m.action, Marker::ADD) << m.ns << m.id;
  EXPECT_EQ(b.shown.pins, (std::set<int>{0, 4}));
  EXPECT_EQ(b.shown.spheres, (std::set<int>{1, 6}));
  EXPECT_TRUE(b.shown.ground);
}

TEST_F(MarkerBuilderTest, NoGroundMarkerWithoutAGround) {
  ground_.enabled = false;
  EXPECT_TRUE(find(build(), names::kGroundNs).empty());
}

TEST_F(MarkerBuilderTest, ARemovedThingIsDeletedOnceAndNothingElseIs) {
  const MarkerBuild first = build();
  pins_.erase(pins_.begin());      // pin 0 gone
  spheres_.pop_back();             // sphere 6 gone
  ground_.enabled = false;         // ground gone
  const MarkerBuild second = build(first.shown);
  std::vector<std::pair<std::string, int>> deleted;
  for (const Marker& m : second.markers.markers) {
    if (m.action == Marker::DELETE) deleted.emplace_back(m.ns, m.id);
  }
  const std::vector<std::pair<std::string, int>> expected = {
      {names::kPinsNs, 0}, {names::kSpheresNs, 6}, {names::kGroundNs, 0}};
  EXPECT_EQ(deleted, expected);

  const MarkerBuild third = build(second.shown);
  for (const Marker& m : third.markers.markers) EXPECT_EQ(m.action, Marker::ADD);
  EXPECT_EQ(third.markers.markers.size(), 1u + 1u + 1u);  // cloth, pin 4, sphere 1
}

TEST_F(MarkerBuilderTest, NonFiniteInputNeverReachesAMarker) {
  positions_(0, 2) = kNaN;
  positions_(1, 5) = kInf;
  positions_(2, 7) = -kInf;
  strain_[3] = kNaN;
  pins_[0].target.x() = kNaN;
  spheres_[0].center.z() = kInf;
  spheres_[1].radius = kNaN;
  const MarkerBuild b = build();
  auto finite = [](const geometry_msgs::Point& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  };
  for (const Marker& m : b.markers.markers) {
    EXPECT_TRUE(finite(m.pose.position)) << m.ns << " " << m.id;
    EXPECT_TRUE(std::isfinite(m.scale.x) && std::isfinite(m.scale.y) && std::isfinite(m.scale.z));
    for (const auto& p : m.points) EXPECT_TRUE(finite(p)) << m.ns;
    for (const auto& c : m.colors) {
      EXPECT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b));
    }
  }
  // Each bad particle coordinate appears once per triangle corner that uses it.
  auto uses = [&](int vertex) { return (triangles_.array() == vertex).count(); };
  EXPECT_EQ(b.sanitized, uses(2) + uses(5) + uses(7) + 1 + 1 + 1);  // pin, centre, radius
}

TEST_F(MarkerBuilderTest, ColoursFollowTheStrainLegendWhenUnshaded) {
  style_.shading = false;
  style_.strain_color_scale = 0.1;
  strain_[0] = 0.1;    // stretched
  strain_[1] = -0.2;   // compressed past the scale
  const MarkerBuild b = build();
  const Marker& cloth = *find(b, names::kClothNs)[0];
  for (Eigen::Index t = 0; t < triangles_.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std_msgs::ColorRGBA expected = strainColor(strain_[triangles_(k, t)], 0.1);
      EXPECT_EQ(cloth.colors[3 * t + k], expected);
    }
  }
}

TEST_F(MarkerBuilderTest, ShadingDarkensByTheShadeFactorOfTheVertexNormal) {
  // The grid is flat in z = 0: every normal is +-z.
  const MarkerBuild b = build();
  const Marker& cloth = *find(b, names::kClothNs)[0];
  const double f = shadeFactor(Vec3(0, 0, 1));
  EXPECT_NEAR(cloth.colors[0].r, f * strainColor(0.0, 1.0).r, 1e-6);
  EXPECT_LT(f, 1.0);
}

TEST_F(MarkerBuilderTest, ShadedModeIsOneColourShadedWhateverTheStrain) {
  // The cloth lying on drape's sphere, stretched, was saturated red: a red ball.
  strain_.setConstant(0.5);  // far past the full-colour strain
  style_.color_mode = ColorMode::kShaded;
  const MarkerBuild b = build();
  const Marker& cloth = *find(b, names::kClothNs)[0];
  const double f = shadeFactor(Vec3(0, 0, 1));
  for (const auto& c : cloth.colors) {
    EXPECT_NEAR(c.r, f * 0.62, 1e-6);
    EXPECT_NEAR(c.g, f * 0.70, 1e-6);
    EXPECT_NEAR(c.b, f * 0.82, 1e-6);
  }
  EXPECT_EQ(colorModeFromName("shaded"), ColorMode::kShaded);
  EXPECT_EQ(colorModeFromName("strain"), ColorMode::kStrain);
  EXPECT_THROW(colorModeFromName("red"), std::invalid_argument);
}

TEST_F(MarkerBuilderTest, MeshObstaclesAreDrawnOnlyWhenGiven) {
  EXPECT_TRUE(find(build(), names::kObstaclesNs).empty());
  TriangleMesh mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0, 1, 0, 0,  //
      0, 0, 1, 0,               //
      0, 0, 0, 1;
  mesh.triangles.resize(3, 2);
  mesh.triangles << 0, 0,  //
      1, 2,                //
      2, 3;
  const std::vector<std::shared_ptr<const MeshObstacle>> obstacles{
      std::make_shared<const MeshObstacle>(mesh, 0.01, 0.0)};
  MarkerScene scene{positions_, triangles_, strain_, pins_, spheres_, ground_, Vec3(0, 0, 0), 4.0,
                    &obstacles};
  const MarkerBuild b = buildMarkers(scene, style_, header_, {});
  const auto drawn = find(b, names::kObstaclesNs);
  ASSERT_EQ(drawn.size(), 1u);
  EXPECT_EQ(drawn[0]->id, 0);
  EXPECT_EQ(drawn[0]->type, Marker::TRIANGLE_LIST);
  ASSERT_EQ(drawn[0]->points.size(), 6u);
  ASSERT_EQ(drawn[0]->colors.size(), 6u);
  // The second triangle (0, 2, 3) in order, at the mesh's coordinates.
  EXPECT_EQ(drawn[0]->points[4].y, 1.0);
  EXPECT_EQ(drawn[0]->points[5].z, 1.0);
  // Flat shaded: one colour per triangle, darker for the face turned from the light.
  EXPECT_EQ(drawn[0]->colors[0].r, drawn[0]->colors[2].r);
  EXPECT_NE(drawn[0]->colors[0].r, drawn[0]->colors[3].r);
}

TEST_F(MarkerBuilderTest, InconsistentInputIsRefused) {
  strain_ = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(build(), std::invalid_argument);
  strain_ = Eigen::VectorXd::Zero(positions_.cols());
  triangles_(1, 2) = 99;
  EXPECT_THROW(build(), std::invalid_argument);
}

TEST(StrainColor, Legend) {
  const auto eq = [](const std_msgs::ColorRGBA& c, double r, double g, double b) {
    return std::abs(c.r - r) < 1e-6 && std::abs(c.g - g) < 1e-6 && std::abs(c.b - b) < 1e-6 &&
           c.a == 1.0f;
  };
  EXPECT_TRUE(eq(strainColor(0.0, 0.05), 0.87, 0.87, 0.87));     // rest: light grey
  EXPECT_TRUE(eq(strainColor(0.05, 0.05), 0.71, 0.02, 0.15));    // stretched: red
  EXPECT_TRUE(eq(strainColor(0.5, 0.05), 0.71, 0.02, 0.15));     // saturates
  EXPECT_TRUE(eq(strainColor(-0.05, 0.05), 0.23, 0.30, 0.75));   // compressed: blue
  EXPECT_TRUE(eq(strainColor(0.025, 0.05), 0.79, 0.445, 0.51));  // halfway to red
  EXPECT_TRUE(eq(strainColor(kNaN, 0.05), 0.87, 0.87, 0.87));    // drawable anyway
}

TEST(ShadeFactor, TwoSidedLambertWithAFloor) {
  const Vec3 light = Vec3(0.3, 0.4, 0.87).normalized();
  EXPECT_NEAR(shadeFactor(light), 1.0, 1e-12);
  EXPECT_NEAR(shadeFactor(-light), 1.0, 1e-12);  // the back face is lit too
  EXPECT_NEAR(shadeFactor(light.unitOrthogonal()), 0.45, 1e-12);
  EXPECT_NEAR(shadeFactor(Vec3::Zero()), 0.45, 1e-12);  // undefined normal: darkest, finite
}

}  // namespace
}  // namespace cloth_sim::node
