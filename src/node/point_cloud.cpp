#include "cloth_sim/node/point_cloud.h"

#include <Eigen/Geometry>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace cloth_sim::node {

Points vertexNormals(const Points& x, const Eigen::Matrix3Xi& triangles) {
  Points n = Points::Zero(3, x.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const int a = triangles(0, t), b = triangles(1, t), c = triangles(2, t);
    const Vec3 ab = x.col(b) - x.col(a), ac = x.col(c) - x.col(a);
    const Vec3 twice_area_normal = ab.cross(ac);
    n.col(a) += twice_area_normal;
    n.col(b) += twice_area_normal;
    n.col(c) += twice_area_normal;
  }
  for (Eigen::Index i = 0; i < n.cols(); ++i) {
    const double length = n.col(i).norm();
    if (length > 0.0) n.col(i) /= length;
  }
  return n;
}

sensor_msgs::PointCloud2 toPointCloud(const Points& x, const Eigen::Matrix3Xi& triangles,
                                      const std_msgs::Header& header) {
  const Points normals = vertexNormals(x, triangles);
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
  sensor_msgs::PointCloud2Iterator<float> p(cloud, "x"), n(cloud, "normal_x");
  for (Eigen::Index i = 0; i < x.cols(); ++i, ++p, ++n) {
    for (int k = 0; k < 3; ++k) {
      p[k] = static_cast<float>(x(k, i));
      n[k] = static_cast<float>(normals(k, i));
    }
  }
  return cloud;
}

}  // namespace cloth_sim::node
