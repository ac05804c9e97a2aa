/// @file body_collider.h
/// Rigid bodies the cloth collides with (a finger, a wrist, a table, a tool): a sphere, capsule,
/// box or triangle mesh, still or following a moving frame, with friction.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The shape of a body, in its own frame.
enum class BodyShape { kSphere, kCapsule, kBox, kMesh };

/// "sphere", "capsule", "box", "mesh".
const char* bodyShapeName(BodyShape shape);
/// The shape called @p name; throws std::invalid_argument listing the names.
BodyShape bodyShapeFromName(const std::string& name);

/// A body's geometry in its own frame (m).
struct BodyGeometry {
  BodyShape shape = BodyShape::kBox;
  double radius = 0.0;       ///< m, sphere and capsule (> 0)
  double length = 0.0;       ///< m, capsule: distance between its two cap centres, along z (>= 0)
  Vec3 size = Vec3::Zero();  ///< m, box: full extents along x, y, z (each > 0), centred
  /// Mesh: the triangles in the body's frame, with the body's margin as its thickness and the
  /// body's friction (shared and immutable: copying a body stays cheap).
  std::shared_ptr<const MeshObstacle> mesh;

  /// Signed distance (m) from @p p (body frame) to the convex shape's surface, negative inside
  /// (sphere, capsule, box; a mesh has none: 0).
  double distance(const Vec3& p) const;
  /// Unit direction of steepest increase of distance() at @p p (outward normal on the surface;
  /// +z where it is undefined).
  Vec3 gradient(const Vec3& p) const;
  /// m, the radius of a ball around the frame's origin that holds the whole shape.
  double boundingRadius() const;
};

/// A rigid body: its geometry placed at `origin` in a frame that is at `frame_pose` at the end of
/// the substep and was at `previous_frame_pose` at its start (the simulation frame, m). A still
/// body has both equal; one that follows a frame is moved by Simulation before every substep
/// (BodySet::place) from the pose source, as grasps are. The cloth keeps `margin` away from its
/// surface.
struct BodyCollider {
  int id = -1;               ///< stable handle, unique within its BodySet
  std::string name;          ///< free label (the node puts the tf frame or the URDF link here)
  BodyGeometry geometry;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< the geometry in the frame
  Eigen::Isometry3d frame_pose = Eigen::Isometry3d::Identity();           ///< substep's end
  Eigen::Isometry3d previous_frame_pose = Eigen::Isometry3d::Identity();  ///< substep's start
  bool follows_frame = false;  ///< moved by the pose source at every substep
  /// False for a body on a frame that the pose source has not placed yet: it touches nothing
  /// (it is nowhere yet), and its first pose is taken without a sweep from the origin.
  bool placed = true;
  double margin = 0.005;       ///< m, (0, 1]: distance the cloth keeps from the surface
  double friction = 0.0;       ///< Coulomb mu in [0, 100]

  /// The geometry's frame in the simulation frame at the substep's end / start.
  Eigen::Isometry3d pose() const { return frame_pose * origin; }
  Eigen::Isometry3d previousPose() const { return previous_frame_pose * origin; }
};

/// Where the frame of body @p id is at simulated time @p time (s), in the simulation frame.
using BodyPoseSource = std::function<Eigen::Isometry3d(int id, double time)>;

/// The bodies of a simulation, with stable ids.
class BodySet {
 public:
  /// Adds @p body (its id is ignored; previous_frame_pose is set to frame_pose) and returns its
  /// id. Throws std::invalid_argument naming the bad field (a size, the margin, the friction,
  /// a non-finite pose, a mesh without triangles), changing nothing.
  int add(const BodyCollider& body);
  /// Throws std::invalid_argument if no body has this id.
  void remove(int id);
  /// Puts body @p id's frame at @p frame_pose now (both ends of the next substep: a teleport).
  /// Throws for an unknown id or a non-finite pose.
  void setFramePose(int id, const Eigen::Isometry3d& frame_pose);
  /// Body @p id, or nullptr.
  const BodyCollider* find(int id) const;
  /// Every body, in the order they were added.
  const std::vector<BodyCollider>& bodies() const { return bodies_; }
  /// True when there is no body.
  bool empty() const { return bodies_.empty(); }
  /// Before a substep ending at simulated time @p time (s): every body's start pose becomes
  /// where it ended the last substep; a body that follows a frame is put where @p source says
  /// (an answer that is not finite keeps the last pose; no source keeps it too). A body's first
  /// pose from the source is taken at both ends: it appears there, sweeping nothing.
  void place(double time, const BodyPoseSource& source);
  /// Ends the motion: each body's start pose is its end pose (after a reset or a restore).
  void settle();

 private:
  std::vector<BodyCollider> bodies_;
  int next_id_ = 0;
};

/// What contact with the bodies does to one particle over one step (after the solve): the
/// particle's path from @p start to @p end (m, simulation frame) is taken into each body's frame
/// (the start at the body's start pose, the end at its end pose), so a body that moves or turns
/// within the step sweeps through the particle and cannot pass it (continuous detection, for
/// convex shapes the first entry of the path into the shape grown by the margin; for a mesh,
/// MeshObstacle::collide). A particle that entered is put back on the surface where it entered,
/// keeping its slide along it less Coulomb friction: the tangential displacement relative to the
/// body's surface is cut by mu times the normal correction, counted up to what the particle's
/// free motion @p free_motion (h v + h^2 g, m, simulation frame; taken relative to each body
/// inside) drove into it (frictionLoad).
///
/// A particle squeezed between bodies (two fingers closing on it: the last push put it inside
/// another body's margin) is placed where the overlaps balance, and friction then presses with
/// the remaining overlaps (m) on its slide relative to the squeezing bodies: the grip of a pinch.
/// Returns whether @p end changed.
bool collideWithBodies(const std::vector<BodyCollider>& bodies, const Vec3& start, Vec3& end,
                       const std::optional<Vec3>& free_motion);

}  // namespace cloth_sim
