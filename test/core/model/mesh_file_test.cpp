// Mesh files (mesh_file.h): binary and ASCII STL give the same triangles, shared corners merged;
// bad files are refused naming the file.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/mesh_file.h"

namespace cloth_sim {
namespace {

/// A unit square in z = 0 as two triangles.
const float kCorners[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}};

std::string binarySquare() {
  std::string bytes(80, ' ');
  const std::uint32_t count = 2;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& tri : kCorners) {
    const float normal[3] = {0, 0, 1};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    for (const auto& v : tri) bytes.append(reinterpret_cast<const char*>(v), 12);
    bytes.append(2, '\0');
  }
  return bytes;
}

std::string asciiSquare() {
  std::string s = "solid square\n";
  for (const auto& tri : kCorners) {
    s += " facet normal 0 0 1\n  outer loop\n";
    for (const auto& v : tri) {
      s += "   vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
           std::to_string(v[2]) + "\n";
    }
    s += "  endloop\n endfacet\n";
  }
  return s + "endsolid square\n";
}

std::string refusal(const std::string& bytes) {
  try {
    parseStl(bytes, "f.stl");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(MeshFile, BinaryAndAsciiStlGiveTheSquare) {
  for (const std::string& bytes : {binarySquare(), asciiSquare()}) {
    const TriangleMesh m = parseStl(bytes, "square.stl");
    EXPECT_EQ(m.vertexCount(), 4);  // the diagonal's corners merged
    EXPECT_EQ(m.triangleCount(), 2);
    EXPECT_DOUBLE_EQ(m.triangleArea(0) + m.triangleArea(1), 1.0);
  }
}

TEST(MeshFile, RefusesBadFilesNamingThem) {
  EXPECT_NE(refusal("not a mesh").find("f.stl: not an STL file"), std::string::npos);
  EXPECT_NE(refusal("solid empty\nendsolid\n").find("f.stl: the STL file has no triangle"),
            std::string::npos);
  EXPECT_NE(refusal("solid x\nfacet\nvertex 0 0 0\nvertex 1 0 0\nendfacet\n").find("2 vertices"),
            std::string::npos);
  EXPECT_NE(refusal("solid x\nfacet\nvertex 0 zero 0\n").find("not three numbers"),
            std::string::npos);
  std::string truncated = binarySquare();
  truncated.resize(truncated.size() - 10);
  EXPECT_NE(refusal(truncated).find("not an STL file"), std::string::npos);
  EXPECT_THROW(loadMeshFile("/nonexistent/part.STL"), std::invalid_argument);
  try {
    loadMeshFile("part.dae");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("must be .obj or .stl"), std::string::npos);
  }
}

TEST(MeshFile, LoadsAnStlFileByItsExtension) {
  const std::string path = ::testing::TempDir() + "mesh_file_test.STL";
  std::ofstream(path, std::ios::binary) << binarySquare();
  EXPECT_EQ(loadMeshFile(path).triangleCount(), 2);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace cloth_sim
