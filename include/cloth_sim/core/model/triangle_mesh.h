/// @file triangle_mesh.h
/// Triangle meshes read from Wavefront OBJ files (tinyobjloader) and checked for use as cloth.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Vertices and triangles of a surface. Column t of @c triangles holds the vertex indices of
/// triangle t.
struct TriangleMesh {
  Points vertices;              ///< m (after any transform)
  Eigen::Matrix3Xi triangles;   ///< vertex indices

  int vertexCount() const { return static_cast<int>(vertices.cols()); }
  int triangleCount() const { return static_cast<int>(triangles.cols()); }
  /// Area of triangle @p t (m^2).
  double triangleArea(int t) const;
  /// The mesh with every vertex mapped by x -> pose * (scale x).
  TriangleMesh transformed(const Eigen::Isometry3d& pose, double scale) const;
};

/// Parses OBJ text (polygons are triangulated as fans, all objects/groups merged, materials,
/// normals and texture coordinates ignored). @p source names it in errors.
/// Throws std::invalid_argument on a syntax error or when there is no face.
TriangleMesh parseObj(const std::string& text, const std::string& source);
/// Reads and parses an OBJ file. Throws std::invalid_argument (also when it cannot be read).
TriangleMesh loadObj(const std::string& path);

/// Checks that @p mesh can be a mass-spring surface, else throws std::invalid_argument naming
/// the offending element: a vertex used by no triangle (it would get no mass), a triangle with
/// a repeated vertex or an area below 1e-12 of the squared bounding-box diagonal (degenerate),
/// an edge shared by more than two triangles (non-manifold), or a non-finite coordinate.
void validateClothSurface(const TriangleMesh& mesh, const std::string& source);

}  // namespace cloth_sim
