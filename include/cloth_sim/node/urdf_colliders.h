/// @file urdf_colliders.h
/// The robot's body as colliders: the collision geometry of chosen links of a URDF
/// (~robot_description, ~robot_links), each a body that follows its link's tf frame.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cloth_sim/core/collision/body_collider.h"

namespace cloth_sim::node {

/// Turns a package:// or file:// mesh name of a URDF into a file path (the node: roslib's
/// package path); throws std::invalid_argument when it cannot.
using MeshPathResolver = std::function<std::string(const std::string& url)>;

/// package://PKG/PATH -> roslib's path of PKG + /PATH; file:///PATH -> /PATH; anything else as
/// it is. Throws std::invalid_argument for an unknown package.
std::string resolveMeshUrl(const std::string& url);

/// The colliders of @p links in the URDF text @p urdf_xml: one body per <collision> element of
/// each link, named by the link and following its frame (BodyCollider::follows_frame, name = the
/// link), at the element's origin, with @p margin (m) and @p friction. A <sphere> is a sphere, a
/// <box> a box, a <cylinder> a capsule of its radius whose cap centres are its end faces' centres
/// (it reaches its radius beyond each flat end), a <mesh> an OBJ or STL mesh (its scale's x; a
/// non-uniform scale is refused). Throws std::invalid_argument naming the problem: a URDF that
/// does not parse, an unknown link, a link without collision geometry, a mesh that cannot be
/// loaded, a size out of range (settings::kBodySize).
std::vector<BodyCollider> urdfColliders(const std::string& urdf_xml,
                                        const std::vector<std::string>& links, double margin,
                                        double friction, const MeshPathResolver& resolve);

}  // namespace cloth_sim::node
