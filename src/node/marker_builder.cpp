#include "cloth_sim/node/marker_builder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "cloth_sim/core/linalg/parallel.h"
#include "cloth_sim/node/point_cloud.h"

namespace cloth_sim::node {
namespace {

using visualization_msgs::Marker;

/// Replaces non-finite numbers by 0 and counts them.
class Sanitizer {
 public:
  double operator()(double v) {
    if (std::isfinite(v)) return v;
    ++count_;
    return 0.0;
  }
  geometry_msgs::Point point(const Vec3& v) {
    geometry_msgs::Point p;
    p.x = (*this)(v.x());
    p.y = (*this)(v.y());
    p.z = (*this)(v.z());
    return p;
  }
  int count() const { return count_; }
  void add(int count) { count_ += count; }

 private:
  int count_ = 0;
};

std_msgs::ColorRGBA rgba(double r, double g, double b, double a) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = static_cast<float>(a);
  return c;
}

Marker makeMarker(const std_msgs::Header& header, const char* ns, int id, int type) {
  Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

Marker makeDelete(const std_msgs::Header& header, const char* ns, int id) {
  Marker m = makeMarker(header, ns, id, Marker::SPHERE);
  m.action = Marker::DELETE;
  return m;
}

Marker makeSphere(const std_msgs::Header& header, const char* ns, int id, const Vec3& center,
                  double diameter, const std_msgs::ColorRGBA& color, Sanitizer& sanitize) {
  Marker m = makeMarker(header, ns, id, Marker::SPHERE);
  m.pose.position = sanitize.point(center);
  m.scale.x = m.scale.y = m.scale.z = sanitize(diameter);
  m.color = color;
  return m;
}

void checkSizes(const MarkerScene& scene) {
  const Eigen::Index n = scene.positions.cols();
  if (scene.strain.size() != n) {
    throw std::invalid_argument("marker builder: " + std::to_string(scene.strain.size()) +
                                " strains for " + std::to_string(n) + " particles");
  }
  if (scene.triangles.size() > 0 &&
      (scene.triangles.minCoeff() < 0 || scene.triangles.maxCoeff() >= n)) {
    throw std::invalid_argument("marker builder: a triangle index is outside [0, " +
                                std::to_string(n) + ")");
  }
}

Marker makeCloth(const MarkerScene& scene, const MarkerStyle& style,
                 const std_msgs::Header& header, Sanitizer& sanitize, int threads) {
  Marker m = makeMarker(header, names::kClothNs, 0, Marker::TRIANGLE_LIST);
  const Points normals =
      style.shading ? vertexNormals(scene.positions, scene.triangles, threads, true) : Points();
  // One colour per particle, shared by the triangle corners that meet there.
  std::vector<std_msgs::ColorRGBA> colors(scene.positions.cols());
  // Shaded: a light blue-grey cloth (a cloth lying on a sphere reads as cloth, not as a red
  // ball); the shading below then gives the shape.
  const std_msgs::ColorRGBA plain = rgba(0.62, 0.70, 0.82, 1.0);
  const BlockSplit particles(static_cast<std::size_t>(scene.positions.cols()), 4096);
  parallelFor(threads, particles.blocks(), [&](int b) {
    for (std::size_t i = particles.begin(b); i < particles.end(b); ++i) {
      colors[i] = style.color_mode == ColorMode::kShaded
                      ? plain
                      : strainColor(scene.strain[i], style.strain_color_scale);
      if (style.shading) {
        const auto f = static_cast<float>(shadeFactor(normals.col(i)));
        colors[i].r *= f;
        colors[i].g *= f;
        colors[i].b *= f;
      }
    }
  });
  // Three corners per triangle, each block of triangles into its own place; each block counts
  // its own non-finite numbers.
  m.points.resize(3 * scene.triangles.cols());
  m.colors.resize(m.points.size());
  const BlockSplit triangles(static_cast<std::size_t>(scene.triangles.cols()), 4096);
  std::vector<Sanitizer> sanitizers(triangles.blocks());
  parallelFor(threads, triangles.blocks(), [&](int b) {
    for (std::size_t t = triangles.begin(b); t < triangles.end(b); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int i = scene.triangles(k, t);
        m.points[3 * t + k] = sanitizers[b].point(scene.positions.col(i));
        m.colors[3 * t + k] = colors[i];
      }
    }
  });
  for (const Sanitizer& block : sanitizers) sanitize.add(block.count());
  return m;
}

Marker makeObstacle(const MeshObstacle& obstacle, int id, const std_msgs::Header& header,
                    Sanitizer& sanitize) {
  Marker m = makeMarker(header, names::kObstaclesNs, id, Marker::TRIANGLE_LIST);
  const TriangleMesh& mesh = obstacle.mesh();
  m.points.reserve(3 * mesh.triangleCount());
  m.colors.reserve(3 * mesh.triangleCount());
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 a = mesh.vertices.col(mesh.triangles(0, t)), b = mesh.vertices.col(mesh.triangles(1, t)),
               c = mesh.vertices.col(mesh.triangles(2, t));
    const Vec3 n = (b - a).cross(c - a).normalized();
    const auto f = static_cast<float>(shadeFactor(n));
    const std_msgs::ColorRGBA color = rgba(0.55 * f, 0.42 * f, 0.30 * f, 1.0);  // wood brown
    for (const Vec3* p : {&a, &b, &c}) {
      m.points.push_back(sanitize.point(*p));
      m.colors.push_back(color);
    }
  }
  return m;
}

}  // namespace

ColorMode colorModeFromName(const std::string& name) {
  for (ColorMode mode : {ColorMode::kStrain, ColorMode::kShaded}) {
    if (name == colorModeName(mode)) return mode;
  }
  throw std::invalid_argument("color mode '" + name.substr(0, 64) +
                              "' must be 'strain' or 'shaded'");
}

const char* colorModeName(ColorMode mode) {
  return mode == ColorMode::kShaded ? "shaded" : "strain";
}

std_msgs::ColorRGBA strainColor(double strain, double scale) {
  const Vec3 compressed(0.23, 0.30, 0.75), rest(0.87, 0.87, 0.87), stretched(0.71, 0.02, 0.15);
  double u = std::isfinite(strain) && scale > 0.0 ? strain / scale : 0.0;
  u = std::clamp(u, -1.0, 1.0);
  const Vec3 c = u < 0.0 ? rest + (-u) * (compressed - rest) : rest + u * (stretched - rest);
  return rgba(c.x(), c.y(), c.z(), 1.0);
}

double shadeFactor(const Vec3& normal) {
  static const Vec3 light = Vec3(0.3, 0.4, 0.87).normalized();
  const double lambert = std::abs(normal.dot(light));
  return 0.45 + 0.55 * (std::isfinite(lambert) ? std::min(lambert, 1.0) : 0.0);
}

MarkerBuild buildMarkers(const MarkerScene& scene, const MarkerStyle& style,
                         const std_msgs::Header& header, const ShownMarkers& before, int threads) {
  checkSizes(scene);
  Sanitizer sanitize;
  MarkerBuild build;
  auto& out = build.markers.markers;
  out.push_back(makeCloth(scene, style, header, sanitize, threads));

  for (const Pin& pin : scene.pins) {
    const auto color = pin.isHard() ? rgba(1.0, 0.55, 0.0, 1.0) : rgba(0.95, 0.85, 0.1, 1.0);
    out.push_back(makeSphere(header, names::kPinsNs, pin.id, pin.target, style.pin_diameter, color,
                             sanitize));
    build.shown.pins.insert(pin.id);
  }
  for (const SphereCollider& s : scene.spheres) {
    out.push_back(makeSphere(header, names::kSpheresNs, s.id, s.center, 2.0 * s.radius,
                             rgba(0.25, 0.55, 0.35, 0.9), sanitize));
    build.shown.spheres.insert(s.id);
  }
  if (scene.ground.enabled) {
    constexpr double kThickness = 0.01;  // m; its top face just below the ground plane
    Marker g = makeMarker(header, names::kGroundNs, 0, Marker::CUBE);
    g.pose.position =
        sanitize.point(Vec3(scene.ground_center.x(), scene.ground_center.y(),
                            scene.ground.height - kGroundDrawGap - 0.5 * kThickness));
    g.scale.x = g.scale.y = sanitize(scene.ground_size);
    g.scale.z = kThickness;
    g.color = rgba(0.75, 0.75, 0.7, 1.0);  // light: lit at a grazing angle it still shows
    out.push_back(g);
    build.shown.ground = true;
  }

  if (scene.obstacles != nullptr) {
    for (std::size_t k = 0; k < scene.obstacles->size(); ++k) {
      out.push_back(makeObstacle(*(*scene.obstacles)[k], static_cast<int>(k), header, sanitize));
    }
  }

  for (int id : before.pins) {
    if (!build.shown.pins.count(id)) out.push_back(makeDelete(header, names::kPinsNs, id));
  }
  for (int id : before.spheres) {
    if (!build.shown.spheres.count(id)) out.push_back(makeDelete(header, names::kSpheresNs, id));
  }
  if (before.ground && !build.shown.ground) out.push_back(makeDelete(header, names::kGroundNs, 0));
  build.sanitized = sanitize.count();
  return build;
}

}  // namespace cloth_sim::node
