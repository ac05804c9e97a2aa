/// @file mesh_builder.h
/// Builds a mass-spring object from any triangle mesh (the original project's "import meshes as
/// non-rigid objects").
#pragma once

#include <string>

#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/model/triangle_mesh.h"

namespace cloth_sim {

/// A triangle mesh and the material that turns it into a mass-spring object.
struct MeshSpec {
  TriangleMesh mesh;          ///< world coordinates (m); checked by validateClothSurface
  std::string source;         ///< names the mesh in error messages
  /// Areal density (kg/m^2): each vertex gets a third of the mass of every triangle around it.
  double areal_density = 0.1;
  bool has_structural = true;
  double structural = 1000.0; ///< N/m, springs on the mesh edges
  bool has_bending = false;
  double bending = 100.0;     ///< N/m, springs across each interior edge (between the two
                              ///< vertices opposite it), resisting folding along that edge
};

/// Builds the particles (area-lumped masses), one structural spring per mesh edge and one
/// bending spring per edge shared by two triangles; rest lengths from the mesh itself.
/// Throws std::invalid_argument for a mesh that fails validateClothSurface or bad material.
BuiltObject buildMeshObject(const MeshSpec& spec);

}  // namespace cloth_sim
