#include "cloth_sim/node/point_cloud.h"

#include <cstring>

#include <Eigen/Geometry>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim::node {

Points vertexNormals(const Points& x, const Eigen::Matrix3Xi& triangles, int threads,
                     bool skip_non_finite) {
  // The triangles' normals in parallel; added to their corners in triangle order (a cheap
  // serial pass); normalised in parallel.
  Points face(3, triangles.cols());
  const BlockSplit faces(static_cast<std::size_t>(triangles.cols()), 2048);
  parallelFor(threads, faces.blocks(), [&](int b) {
    for (std::size_t t = faces.begin(b); t < faces.end(b); ++t) {
      const int a = triangles(0, t), bb = triangles(1, t), c = triangles(2, t);
      const Vec3 ab = x.col(bb) - x.col(a), ac = x.col(c) - x.col(a);
      face.col(t) = ab.cross(ac);
    }
  });
  Points n = Points::Zero(3, x.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    if (skip_non_finite && !face.col(t).allFinite()) continue;
    for (int k = 0; k < 3; ++k) n.col(triangles(k, t)) += face.col(t);
  }
  const BlockSplit vertices(static_cast<std::size_t>(x.cols()), 2048);
  parallelFor(threads, vertices.blocks(), [&](int b) {
    for (std::size_t i = vertices.begin(b); i < vertices.end(b); ++i) {
      const double length = n.col(i).norm();
      if (length > 0.0) n.col(i) /= length;
    }
  });
  return n;
}

sensor_msgs::PointCloud2 toPointCloud(const Points& x, const Eigen::Matrix3Xi& triangles,
                                      const std_msgs::Header& header, int threads) {
  const Points normals = vertexNormals(x, triangles, threads);
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                                sensor_msgs::PointField::FLOAT32, "z", 1,
                                sensor_msgs::PointField::FLOAT32, "normal_x", 1,
                                sensor_msgs::PointField::FLOAT32, "normal_y", 1,
                                sensor_msgs::PointField::FLOAT32, "normal_z", 1,
                                sensor_msgs::PointField::FLOAT32);
  modifier.resize(static_cast<std::size_t>(x.cols()));
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(x.cols());
  cloud.is_dense = true;
  // Point i at i * point_step; each field at its offset (the iterators' layout, by index).
  std::uint32_t position = 0, normal = 0;
  for (const sensor_msgs::PointField& field : cloud.fields) {
    if (field.name == "x") position = field.offset;
    if (field.name == "normal_x") normal = field.offset;
  }
  const BlockSplit points(static_cast<std::size_t>(x.cols()), 4096);
  parallelFor(threads, points.blocks(), [&](int b) {
    for (std::size_t i = points.begin(b); i < points.end(b); ++i) {
      std::uint8_t* point = cloud.data.data() + i * cloud.point_step;
      const float p[3] = {static_cast<float>(x(0, i)), static_cast<float>(x(1, i)),
                          static_cast<float>(x(2, i))};
      const float q[3] = {static_cast<float>(normals(0, i)), static_cast<float>(normals(1, i)),
                          static_cast<float>(normals(2, i))};
      std::memcpy(point + position, p, sizeof p);
      std::memcpy(point + normal, q, sizeof q);
    }
  });
  return cloud;
}

}  // namespace cloth_sim::node
