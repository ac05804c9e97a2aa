/// @file marker_builder.h
/// Core state -> visualization_msgs/MarkerArray for cloth/markers. Pure: no ROS handle, no clock.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include <std_msgs/ColorRGBA.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {

/// m: the ground's top face is drawn this far below the ground plane, so that a cloth lying on
/// it (at the plane's height) does not flicker through it in RViz (z-fighting).
inline constexpr double kGroundDrawGap = 0.002;

/// Everything drawn, in ~frame_id (m). References must outlive the build.
struct MarkerScene {
  const Points& positions;                     ///< one column per particle
  const Eigen::Matrix3Xi& triangles;           ///< particle indices of each surface triangle
  const Eigen::VectorXd& strain;               ///< signed strain per particle (vertexStrain)
  const std::vector<Pin>& pins;
  const std::vector<SphereCollider>& spheres;
  GroundPlane ground;                          ///< drawn only when enabled
  Vec3 ground_center = Vec3::Zero();           ///< m, the ground square is centred below this
  double ground_size = 3.0;                    ///< m, side of the ground square
  /// Static mesh obstacles (id = index), or nullptr to leave them out of this array: they never
  /// move, so the node sends them only now and then (RViz keeps a marker until it is deleted).
  const std::vector<std::shared_ptr<const MeshObstacle>>* obstacles = nullptr;
};

/// What the cloth's colour shows (~color_mode, dynamic_reconfigure color_mode).
enum class ColorMode {
  kStrain,  ///< "strain": blue compressed, grey at rest, red stretched (strainColor)
  kShaded,  ///< "shaded": one cloth colour, only the shading: the shape, not the strain
};
/// "strain" or "shaded" -> the mode; throws std::invalid_argument listing both.
ColorMode colorModeFromName(const std::string& name);
/// The mode's name, "strain" or "shaded" (the inverse of colorModeFromName).
const char* colorModeName(ColorMode mode);

/// How things look.
struct MarkerStyle {
  ColorMode color_mode = ColorMode::kStrain;
  double strain_color_scale = 0.05;  ///< |strain| drawn at full colour (0.05 = 5 %)
  bool shading = true;               ///< darken cloth colours by a fixed light (see shadeFactor)
  double pin_diameter = 0.04;        ///< m
};

/// Which pin and sphere markers the previous array showed: a later build sends DELETE for
/// the ones that are gone, and only for them.
struct ShownMarkers {
  std::set<int> pins;
  std::set<int> spheres;
  bool ground = false;
};

/// One built array and what it shows.
struct MarkerBuild {
  visualization_msgs::MarkerArray markers;
  ShownMarkers shown;
  /// Non-finite numbers that were replaced by 0 (a coordinate, scale or colour); the core never
  /// produces one (it rolls back), so any count here is worth a warning.
  int sanitized = 0;
};

/// Builds the array (one marker namespace per layer: names::kClothNs, ...; ids are stable: the
/// cloth and the ground are id 0, a pin or a sphere uses its core id): the cloth as one
/// TRIANGLE_LIST with a colour per point (strainColor, shaded), a SPHERE per pin and per sphere
/// collider, the ground, the mesh obstacles when given (flat shaded, one colour); every marker ADD
/// (add or modify in place), plus a DELETE for each pin or sphere of @p before that no longer
/// exists. Every coordinate is finite (see MarkerBuild::sanitized). Throws std::invalid_argument if
/// the strain size differs from the particle count or a triangle index is out of range. The
/// cloth's normals, colours and corners are built on up to @p threads threads (the same array
/// for any count).
MarkerBuild buildMarkers(const MarkerScene& scene, const MarkerStyle& style,
                         const std_msgs::Header& header, const ShownMarkers& before,
                         int threads = 1);

/// Colour legend of the cloth: blue (0.23, 0.30, 0.75) at strain <= -scale (compressed),
/// light grey (0.87, 0.87, 0.87) at 0 (rest length), red (0.71, 0.02, 0.15) at >= +scale
/// (stretched), linear in between; alpha 1. A non-finite strain is drawn as 0.
std_msgs::ColorRGBA strainColor(double strain, double scale);

/// Brightness factor in [0.45, 1] for a surface with unit normal @p normal under a fixed light
/// from (0.3, 0.4, 0.87) (above, to one side), two-sided: both faces of the cloth are lit.
double shadeFactor(const Vec3& normal);

}  // namespace cloth_sim::node
