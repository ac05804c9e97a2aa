/// @file body_messages.h
/// Rigid-body colliders <-> messages: a cloth/add_collider request into a BodyCollider, a body
/// into ColliderInfo, and the bodies' markers. Pure (no master).
#pragma once

#include <set>
#include <string>
#include <vector>

#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <cloth_sim/AddCollider.h>
#include <cloth_sim/ColliderInfo.h>

#include "cloth_sim/core/collision/body_collider.h"
#include "cloth_sim/node/urdf_colliders.h"

namespace cloth_sim::node {

/// The body a cloth/add_collider request describes, its origin in the request's frame (the
/// caller places the frame). Defaults: margin 0 -> 0.005 m, mesh_scale 0 -> 1, a zero
/// quaternion -> identity. Throws std::invalid_argument naming the field (shape, a size, the
/// margin, the friction, a non-finite or non-unit origin, a mesh file that does not load).
BodyCollider bodyFromRequest(const AddCollider::Request& request, const MeshPathResolver& resolve);

/// ColliderInfo of @p body whose frame is @p frame_id (~frame_id for a still one).
ColliderInfo toColliderInfo(const BodyCollider& body, const std::string& frame_id, bool stale);

/// One marker per body in namespace names::kBodiesNs (id = body id), in the simulation frame of
/// @p header: SPHERE, CYLINDER with two SPHERE caps (ids id, 1000000 + id, 2000000 + id), CUBE,
/// TRIANGLE_LIST for a mesh; grey-green, translucent. A body not placed yet is not drawn. DELETEs
/// for the ids of @p shown no longer there; @p shown becomes the ids drawn.
void appendBodyMarkers(const std::vector<BodyCollider>& bodies, const std_msgs::Header& header,
                       std::set<int>& shown, visualization_msgs::MarkerArray& out);

}  // namespace cloth_sim::node
