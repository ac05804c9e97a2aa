/// @file point_cloud.h
/// Particles -> sensor_msgs/PointCloud2 for cloth/points. Pure.
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim::node {

/// Unit normal per particle (3 x N): the area-weighted mean of the normals of the triangles
/// around it (the cross product of two edges is twice the area times the normal, so summing
/// them weights by area). A particle in no triangle, or whose triangles cancel, gets (0, 0, 0).
/// With @p skip_non_finite, a triangle whose normal is not finite adds nothing. The triangles'
/// normals and the normalisation run on up to @p threads threads (the same bits for any count:
/// each particle adds its triangles' normals in triangle order).
Points vertexNormals(const Points& positions, const Eigen::Matrix3Xi& triangles,
                     int threads = 1, bool skip_non_finite = false);

/// An unorganized cloud (height 1, width N, dense) of float32 fields x, y, z, normal_x,
/// normal_y, normal_z: particle i is point i, in @p header's frame (m). Built on up to
/// @p threads threads (the same message for any count).
sensor_msgs::PointCloud2 toPointCloud(const Points& positions, const Eigen::Matrix3Xi& triangles,
                                      const std_msgs::Header& header, int threads = 1);

}  // namespace cloth_sim::node
