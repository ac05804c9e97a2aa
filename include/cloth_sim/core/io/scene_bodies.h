/// @file scene_bodies.h
/// The scene's rigid bodies (colliders.bodies[]): spheres, capsules, boxes and OBJ/STL meshes,
/// still or on a named frame.
#pragma once

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "cloth_sim/core/collision/body_collider.h"
#include "cloth_sim/core/io/scene_fields.h"

namespace cloth_sim {

/// Reads colliders.bodies[] from @p node (a list) into @p out; each entry is
/// {shape, name, frame, radius, length, size, file, scale, position, orientation_rpy, margin,
/// friction} (docs/scene_format.md). Without `frame` the body is still, placed at
/// position/orientation_rpy; with it, that is its origin in the frame and it follows the frame
/// (its name is the frame's; the program running the scene says where the frame is). Throws
/// SceneError naming the field.
void readBodyColliders(const SceneFields& r, const YAML::Node& node, std::vector<BodyCollider>& out);

/// The pose of position [m] and orientation_rpy [rad] of @p node (fixed-axis roll about X,
/// then pitch about Y, then yaw about Z, REP-103), both optional.
Eigen::Isometry3d readScenePose(const SceneFields& r, const YAML::Node& node,
                                const std::string& path);

}  // namespace cloth_sim
