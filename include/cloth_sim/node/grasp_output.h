/// @file grasp_output.h
/// Grasps -> messages: their wrench in the grasp frame, GraspInfo, and an arrow marker. Pure.
#pragma once

#include <set>
#include <string>

#include <geometry_msgs/Wrench.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <cloth_sim/GraspInfo.h>

#include "cloth_sim/core/simulation/grasp.h"
#include "cloth_sim/node/grasp_frames.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {

/// @p grasp's wrench (Grasp::wrench, simulation frame) as ROS reads a WrenchStamped whose header
/// names the tf frame the grasp follows: force and torque in that frame's axes (rotated by R^T,
/// R the frame's rotation), the torque about that frame's origin. The core's torque is about the
/// grasp point, the frame's origin plus @p offset (m, in the frame): moved to the frame's origin
/// it gains offset x F.
geometry_msgs::Wrench wrenchInGraspFrame(const Grasp& grasp, const Vec3& offset);

/// The GraspInfo of @p grasp, tracked by the node as @p tracked.
GraspInfo toGraspInfo(const Grasp& grasp, const GraspFrames::Tracked& tracked);

/// An ARROW (namespace names::kGraspsNs, id = grasp id) from the grasp frame's origin along the
/// force the cloth exerts on it, @p scale m per N long (magenta; red while the frame is stale), in
/// the simulation frame of @p header.
visualization_msgs::Marker graspArrow(const Grasp& grasp, bool stale, double scale,
                                      const std_msgs::Header& header);

/// Appends an arrow per grasp of @p grasps and a DELETE per id of @p shown no longer there;
/// @p shown becomes the ids drawn.
void appendGraspMarkers(const std::vector<Grasp>& grasps, const GraspFrames& frames, double scale,
                        const std_msgs::Header& header, std::set<int>& shown,
                        visualization_msgs::MarkerArray& out);

}  // namespace cloth_sim::node
