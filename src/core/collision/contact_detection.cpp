// The contact detection of ContactForces (contact_forces.h): which features of the cloth touch
// which collider in a step. Each loop runs in fixed blocks on the threads and appends its
// contacts in block order, the serial order.
#include <algorithm>
#include <cmath>
#include <set>

#include "cloth_sim/core/collision/contact_forces.h"
#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {
namespace {

/// A point within this many radii of a sphere (along its relative path) becomes a candidate.
constexpr double kMarginRadii = 0.5;

/// Contact normal for a point whose path relative to a sphere of radius @p r goes from @p a to
/// @p b; false if the path stays farther than @p reach from the centre.
bool sweptNormal(const Vec3& a, const Vec3& b, double r, double reach, Vec3& normal, bool& swept) {
  swept = false;
  const Vec3 path = b - a;
  const double len2 = path.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(path) / len2, 0.0, 1.0) : 0.0;
  if ((a + t * path).norm() > reach) return false;
  // A sweep (the point moves by more than half a radius relative to the sphere, or would pass
  // its centre): push it back out where it entered. A resting or rolling contact uses the
  // radial direction: the entry point of a slow slide lies ahead of the contact and would tilt
  // the force into a drag.
  const bool sweep = std::sqrt(len2) > 0.5 * r || b.dot(a) <= 0.0;
  if (sweep && a.squaredNorm() > r * r && len2 > 0.0) {
    const double enter = sphereEntry(a, path, r);
    if (enter >= 0.0) {
      normal = (a + enter * path).normalized();
      swept = true;
      return true;
    }
  }
  if (b.norm() > 1e-12) normal = b.normalized();
  else normal = a.norm() > 1e-12 ? Vec3(a.normalized()) : Vec3::UnitZ();
  return true;
}

}  // namespace

void ContactForces::boxFeatures(const Model& model, const Points& y) {
  // Shared by every dynamic sphere of the step: one box per movable feature, built once.
  features_.clear();
  feature_boxes_.clear();
  std::vector<Eigen::AlignedBox3d> vertex_box(y.cols());
  const BlockSplit vertices(static_cast<std::size_t>(y.cols()), 1024);
  parallelFor(threads_, vertices.blocks(), [&](int b) {
    for (std::size_t i = vertices.begin(b); i < vertices.end(b); ++i) {
      vertex_box[i].extend(Vec3(start_.col(i))).extend(Vec3(y.col(i)));
    }
  });
  const bool triangles = model.triangles.cols() > 0;
  const BlockSplit split(static_cast<std::size_t>(triangles ? model.triangles.cols() : y.cols()), 1024);
  std::vector<std::vector<std::pair<Feature, Eigen::AlignedBox3d>>> found(split.blocks());
  parallelFor(threads_, split.blocks(), [&](int b) {
    auto add = [&](const std::array<int, 3>& v, int count) {
      Eigen::AlignedBox3d box;
      for (int j = 0; j < count; ++j) {
        if (!movable_[v[j]]) return;  // a pinned vertex cannot be pushed
        box.extend(vertex_box[v[j]]);
      }
      found[b].emplace_back(Feature{v, count}, box);
    };
    for (std::size_t t = split.begin(b); t < split.end(b); ++t) {
      if (triangles) add({model.triangles(0, t), model.triangles(1, t), model.triangles(2, t)}, 3);
      else add({static_cast<int>(t), 0, 0}, 1);
    }
  });
  for (const auto& block : found) {  // in block order: the serial order
    for (const auto& [feature, box] : block) {
      features_.push_back(feature);
      feature_boxes_.push_back(box);
    }
  }
}

void ContactForces::addCandidates(std::size_t k, const Points& y) {
  const Points& start = start_;
  const Body& body = bodies_[k];
  const double reach = body.radius * (1.0 + kMarginRadii);
  Eigen::AlignedBox3d swept;
  swept.extend(body.old).extend(body.predicted);
  swept.min().array() -= reach;
  swept.max().array() += reach;
  // Each feature near the path gives a candidate (in parallel blocks); the first candidate of
  // each distinct feature (vertex, edge, face: shared by triangles) is kept, in feature order.
  struct Candidate {
    Contact contact;
    std::array<int, 3> feature;
    bool touches;
  };
  auto consider = [&](const std::array<int, 3>& v, int count) {
    Contact c{v, {1.0, 0.0, 0.0}, static_cast<int>(k), Vec3::UnitZ(), 0.0, 0.0};
    if (count == 3) {
      // The triangle's point closest to the sphere, as barycentric weights for the step.
      const Vec3 q = closestPointOnTriangle(body.predicted, y.col(v[0]), y.col(v[1]), y.col(v[2]));
      c.weight = barycentric(q, y.col(v[0]), y.col(v[1]), y.col(v[2]));
    }
    std::array<int, 3> feature{-1, -1, -1};
    for (int j = 0, n = 0; j < 3; ++j) {
      if (c.weight[j] > 1e-9) feature[n++] = c.vertex[j];
      else c.weight[j] = 0.0;
    }
    std::sort(feature.begin(), feature.end());
    Vec3 at_start = Vec3::Zero(), at_end = Vec3::Zero();
    for (int j = 0; j < 3; ++j) {
      at_start += c.weight[j] * start.col(c.vertex[j]);
      at_end += c.weight[j] * y.col(c.vertex[j]);
    }
    const bool touches = sweptNormal(at_start - body.old, at_end - body.predicted, body.radius,
                                     reach, c.normal, c.sweep);
    c.triangle = count == 3;
    c.source = body.id;
    return Candidate{c, feature, touches};
  };
  const BlockSplit split(features_.size(), 1024);
  std::vector<std::vector<Candidate>> found(split.blocks());
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t f = split.begin(b); f < split.end(b); ++f) {
      if (feature_boxes_[f].intersects(swept)) found[b].push_back(consider(features_[f].vertex, features_[f].count));
    }
  });
  std::set<std::array<int, 3>> seen;
  for (const auto& block : found) {
    for (const Candidate& candidate : block) {
      if (seen.insert(candidate.feature).second && candidate.touches) contacts_.push_back(candidate.contact);
    }
  }
}

void ContactForces::addStillCandidates(const Model& model, const Points& y) {
  // Reach beyond the step's free motion: about a quarter spacing, what the springs move a
  // particle within one step at most in a resting drape.
  const std::vector<double>& rest = model.springs.rest_length;
  const BlockSplit springs(rest.size(), 4096);
  const double spacing = orderedSum(threads_, springs.blocks(), [&](int b) {
    double sum = 0.0;
    for (std::size_t k = springs.begin(b); k < springs.end(b); ++k) sum += rest[k];
    return sum;
  });
  const double margin = model.springs.size() > 0 ? 0.25 * spacing / model.springs.size() : 0.0;
  // Particles in blocks on the threads, their contacts appended in block order.
  const BlockSplit particles(static_cast<std::size_t>(y.cols()), 256);
  std::vector<std::vector<Contact>> found(particles.blocks());
  parallelFor(threads_, particles.blocks(), [&](int b) {
  for (Eigen::Index p = particles.begin(b); p < static_cast<Eigen::Index>(particles.end(b)); ++p) {
    if (!movable_[p]) continue;
    const Vec3 start = start_.col(p);
    const double reach = (Vec3(y.col(p)) - start).norm() + margin;
    auto add = [&](const Vec3& normal, const Vec3& anchor, int source, double mu) {
      Contact c{{static_cast<int>(p), static_cast<int>(p), static_cast<int>(p)}, {1.0, 0.0, 0.0}, -1,
                normal, 0.0, 0.0};
      c.anchor = anchor;
      c.source = source;
      c.mu = mu;
      found[b].push_back(c);
    };
    if (ground_.enabled && start.z() < ground_.height + reach) {
      add(Vec3::UnitZ(), Vec3(start.x(), start.y(), ground_.height), stillSource(-1), ground_.friction);
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      Vec3 point, normal;
      if (meshes_[m]->nearest(start, reach + meshes_[m]->thickness(), point, normal)) {
        add(normal, point + meshes_[m]->thickness() * normal, stillSource(static_cast<int>(m)),
            meshes_[m]->friction());
      }
    }
  }
  });
  for (const auto& block : found) contacts_.insert(contacts_.end(), block.begin(), block.end());
}

}  // namespace cloth_sim
