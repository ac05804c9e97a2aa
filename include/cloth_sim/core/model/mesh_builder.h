/// @file mesh_builder.h
/// Builds a mass-spring object from any triangle mesh (the original project's "import meshes as
/// non-rigid objects").
#pragma once

#include <string>

#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/model/triangle_mesh.h"

namespace cloth_sim {

/// @p material without the shear family (a mesh has no quads to shear).
inline Material withoutShear(Material material) {
  material.has_shear = false;
  return material;
}

/// A triangle mesh and the material that turns it into a mass-spring object.
struct MeshSpec {
  TriangleMesh mesh;          ///< world coordinates (m); checked by validateClothSurface
  std::string source;         ///< names the mesh in error messages
  /// Each vertex gets a third of the mass of every triangle around it; structural springs lie
  /// on the mesh edges, bending springs across each interior edge (between the two vertices
  /// opposite it), resisting folding along that edge. No shear family: has_shear must be false.
  Material material = withoutShear(Material{});
};

/// Builds the particles (area-lumped masses), one structural spring per mesh edge and one
/// bending spring per edge shared by two triangles; rest lengths from the mesh itself.
/// Throws std::invalid_argument for a mesh that fails validateClothSurface or bad material.
BuiltObject buildMeshObject(const MeshSpec& spec);

}  // namespace cloth_sim
