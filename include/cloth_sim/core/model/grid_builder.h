/// @file grid_builder.h
/// Builds a rectangular cloth grid as a mass-spring Model.
#pragma once

#include <Eigen/Geometry>

#include "cloth_sim/core/model/material.h"
#include "cloth_sim/core/model/model.h"

namespace cloth_sim {

/// Which quad diagonals become shear springs.
enum class ShearPattern {
  kBoth,      ///< both diagonals of every quad (symmetric shear response)
  kTriangle,  ///< only the diagonal (r, c)-(r+1, c+1) that splits the quad into the two
              ///< rendered triangles: with bending this is Liu et al.'s cloth topology
};

/// A rows x cols grid of particles spanning width x height metres.
///
/// In the grid's local frame the sheet lies in z = 0, centred on the origin: column c is at
/// x = -width/2 + c width/(cols-1), row r at y = +height/2 - r height/(rows-1) (row 0 on top).
/// @c pose maps that frame into the world. Vertex index = r * cols + c.
struct GridSpec {
  int rows = 2;                  ///< particles along y (settings::kGridResolution)
  int cols = 2;                  ///< particles along x (settings::kGridResolution)
  double width = 1.0;            ///< m, along local x (settings::kGridSize)
  double height = 1.0;           ///< m, along local y (settings::kGridSize)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< local grid frame -> world
  /// Mass (lumped: each particle gets its share of the sheet, an interior cell, half at edges,
  /// a quarter at corners, so the total is density*width*height) and stiffness per family.
  Material material;
  ShearPattern shear_pattern = ShearPattern::kBoth;  ///< which diagonals shear springs take

  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// A model and its rest positions.
struct BuiltObject {
  Model model;
  Points rest_positions;  ///< m, world frame
};

/// Builds the particles (lumped masses), the springs of the chosen families (rest lengths from
/// the rest positions) and the two triangles of every quad. Gravity, damping and the time step
/// keep Model's defaults: the scene sets them.
BuiltObject buildGrid(const GridSpec& spec);

/// Vertex index of (row, col) in a grid of @p cols columns.
inline int gridVertex(int row, int col, int cols) { return row * cols + col; }

}  // namespace cloth_sim
