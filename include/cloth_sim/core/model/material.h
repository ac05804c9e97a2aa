/// @file material.h
/// What a cloth is made of, the same struct for a grid (grid_builder.h) and a mesh
/// (mesh_builder.h). The scene's 'material' map (docs/scene_format.md) fills it.
#pragma once

namespace cloth_sim {

/// Mass and spring stiffness of a cloth. The allowed range of each field is its entry in
/// settings/settings_table.h (settings::kArealDensity, settings::kStructuralStiffness, ...).
struct Material {
  /// Areal density (kg/m^2): each particle gets the mass of its share of the surface.
  double areal_density = 0.1;
  /// Stiffness (N/m) per family; a family with has_* false is not created at all.
  bool has_structural = true;
  double structural = 1000.0;
  bool has_shear = true;  ///< grid only: a mesh has no quads to shear
  double shear = 1000.0;
  bool has_bending = false;
  double bending = 100.0;

  /// Throws std::invalid_argument "<setting> = <value> must be <rule>" for the first field out
  /// of its range (a family's stiffness only when the family is created).
  void validate() const;
};

}  // namespace cloth_sim
