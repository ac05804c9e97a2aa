#include <gtest/gtest.h>

#include "cloth_sim/core/model/triangle_mesh.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

void expectRefused(const TriangleMesh& mesh, const std::string& fragment) {
  try {
    validateClothSurface(mesh, "m.obj");
    ADD_FAILURE() << "accepted; expected '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("m.obj: ", 0), 0u) << e.what();
  }
}

TEST(TriangleMesh, QuadFaceIsTriangulated) {
  const TriangleMesh m = loadObj(test::sourcePath("test/data/quad.obj"));
  EXPECT_EQ(m.vertexCount(), 4);
  EXPECT_EQ(m.triangleCount(), 2);
  EXPECT_NEAR(m.triangleArea(0) + m.triangleArea(1), 1.0, 1e-12);
  EXPECT_NO_THROW(validateClothSurface(m, "quad"));
}

TEST(TriangleMesh, TransformScalesThenPlaces) {
  const TriangleMesh m = loadObj(test::sourcePath("test/data/quad.obj"));
  const Eigen::Isometry3d pose = Eigen::Translation3d(0, 0, 2) * Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ());
  const TriangleMesh t = m.transformed(pose, 3.0);
  EXPECT_NEAR((t.vertices.col(1) - Vec3(0, 3, 2)).norm(), 0.0, 1e-12);  // (1,0,0) -> scaled, turned, lifted
  EXPECT_NEAR(t.triangleArea(0) + t.triangleArea(1), 9.0, 1e-12);
}

TEST(TriangleMesh, RefusesMeshesThatCannotBeCloth) {
  expectRefused(loadObj(test::sourcePath("test/data/nonmanifold.obj")),
                "non-manifold edge (0, 1) is shared by 3 triangles (0, 1, 2)");
  expectRefused(loadObj(test::sourcePath("test/data/degenerate.obj")), "triangle 1 (0, 1, 3) is degenerate");
  TriangleMesh unused = loadObj(test::sourcePath("test/data/quad.obj"));
  unused.vertices.conservativeResize(3, 5);
  unused.vertices.col(4) = Vec3(5, 5, 5);
  expectRefused(unused, "vertex 4 belongs to no triangle");
  TriangleMesh repeated = loadObj(test::sourcePath("test/data/quad.obj"));
  repeated.triangles(2, 1) = repeated.triangles(0, 1);
  expectRefused(repeated, "repeats a vertex");
  TriangleMesh nan = loadObj(test::sourcePath("test/data/quad.obj"));
  nan.vertices(0, 2) = NAN;
  expectRefused(nan, "non-finite");
}

TEST(TriangleMesh, UnreadableOrFacelessFilesAreReported) {
  try {
    loadObj("/nonexistent/cloth.obj");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cloth.obj: cannot open"), std::string::npos);
  }
  EXPECT_THROW(parseObj("v 0 0 0\nv 1 0 0\n", "points.obj"), std::invalid_argument);
}

TEST(TriangleMesh, ShippedMeshesAreValid) {
  const TriangleMesh cloth = loadObj(test::sourcePath("config/meshes/round_cloth.obj"));
  EXPECT_EQ(cloth.vertexCount(), 1261);
  EXPECT_EQ(cloth.triangleCount(), 2400);
  EXPECT_NO_THROW(validateClothSurface(cloth, "round_cloth"));
  double area = 0.0;
  for (int t = 0; t < cloth.triangleCount(); ++t) area += cloth.triangleArea(t);
  // An inscribed 120-gon of radius 0.6 m: area = 60 r^2 sin(2 pi / 120) (to the file's 1e-6 m).
  EXPECT_NEAR(area, 60 * 0.36 * std::sin(2 * M_PI / 120), 1e-5);
  EXPECT_EQ(loadObj(test::sourcePath("config/meshes/table.obj")).triangleCount(), 12);
}

}  // namespace
}  // namespace cloth_sim
