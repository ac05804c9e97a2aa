// Randomized contact test: a cloth dropped or dragged onto kinematic spheres, boxes (closed
// 12-triangle MeshObstacle) and the ground, at a configuration under test (substeps n, iterations
// per substep, solver), against the same scene run at a small step (the reference).
//
// Each scene must end with
//   (a) no particle inside a collider (sphere |x-c| >= r - tol, box: not inside the box shrunk
//       by tol, ground z >= height - tol), tol = 1 mm;
//   (b) no structural or shear spring passing through a collider: the segment may dip into the
//       collider only as deep as a straight chord of its (rest length x 1.5) whose ends are on the
//       surface can (sphere: r - sqrt(r^2 - (l/2)^2); box edge: l / (2 sqrt 2)), plus tol. A
//       spring torn across the collider (one end on top, the other on the ground beside it)
//       goes far deeper. Bending springs skip (b): they span 2 spacings and may legitimately cross
//       a 1-spacing ball;
//   (c) max strain |l - r| / r of the structural springs (the ones that hold the cloth's
//       length: stretch and tearing show there; the soft shear (40 N/m) and bending (4 N/m)
//       springs deform by 10-50 % in any fold or drape, which says nothing about contact) within max(2 x ref, ref + 0.05) of the reference's, where
//       ref is the reference's final max strain: 2x as asked, with an absolute floor of 5 %
//       strain so that 2x of a near-zero strain (a cloth lying flat) is not stricter than the
//       solver's own iteration error.
//
// The configuration under test defaults to the smallest one that passes all scenes (see
// kDefault* below); CONTACT_RANDOM_SUBSTEPS, CONTACT_RANDOM_ITERATIONS, CONTACT_RANDOM_SOLVER,
// CONTACT_RANDOM_SCENES, CONTACT_RANDOM_SEED, CONTACT_RANDOM_REF_SUBSTEPS and
// CONTACT_RANDOM_REF_ITERATIONS override it (CONTACT_RANDOM_ONLY=3,14 runs only those scenes), e.g. to measure n = 1
// (local_global, 10 iterations, one step per frame). CONTACT_RANDOM_REPORT=1 prints
// every scene's result without failing, for measuring a configuration.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/model/triangle_mesh.h"
#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim {
namespace {

// The asserted configuration: the cheapest that passes all 50 scenes (seed 20261123; failing
// scenes and the checks that failed, a/b/c; n substeps of h = (1/60)/n per frame, local_global):
//   before (post-solve projection only; in-solve contacts for dynamic balls only):
//     n = 1, 10 it: 28 fail   n = 2, 10 it: 28   n = 4, 3 it: 17 (a 0, b 2, c 16)
//     n = 4, 10 it: 17        n = 8,  2 it:  7   n = 8, 5 it:  7   n = 16, 3 it: 2   n = 16, 5 it: 1
//     (mostly (c): cloth hooked on a box's top edge, one particle on the top, its neighbour on
//     the side face, the spring stretched 46-220 % and held there by the projection's friction
//     on the springs' own pull into the face; and round balls resting on the ground);
//   after (contact forces in the solve for the ground and the meshes, friction from the contact force;
//   see docs/method.md, "Contact forces and projection"):
//     n = 2, 5 it: 1 fail (a 0, b 0, c 1)   n = 4, 2 it: 1 (c 1)   n = 4, 3 it: 2 (c 2)
//     n = 4, 5 it: 0 or 1 (scene 39 at the limit, 0.0597 vs 0.0591)
//     n = 8, 2 it: 0                         n = 8, 3 it: 0
//     (the rest: small balls resting on the ground, scenes 39 and 46: kinematic spheres are
//     still projection-only).
// The reference (n = 16, 10 iterations) takes most of the runtime.
constexpr int kDefaultSubsteps = 8;
constexpr int kDefaultIterations = 2;
constexpr const char* kDefaultSolver = "local_global";
constexpr int kDefaultScenes = 50;
constexpr unsigned kDefaultSeed = 20261123;

constexpr double kFrame = 1.0 / 60.0;
constexpr double kTol = 1e-3;            // m, tolerance of checks (a) and (b)
constexpr double kBoxThickness = 0.005;  // m, MeshObstacle thickness (scene files' default)
constexpr int kRefSubsteps = 16;         // reference: h = 1/960 ...
constexpr int kRefIterations = 10;       // ... local_global, 10 iterations (20 doubles the cost
                                         // for final strains within the drag scenes' own scatter)

int envInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}
std::string envString(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

struct Config {
  int substeps = 1;  ///< 0: chosen by the error estimate (error_tolerance > 0)
  int iterations = 10;
  std::string solver = "local_global";
  Integrator integrator = Integrator::kImplicitEuler;
  double error_tolerance = 0.0;  ///< m per frame; 0: fixed iterations
  std::string describe() const {
    std::ostringstream s;
    s << solver << "/" << integratorName(integrator) << ", ";
    if (substeps == 0) s << "substeps by the error estimate";
    else s << "n = " << substeps << " substeps (h = 1/" << std::lround(substeps / kFrame) << ")";
    if (error_tolerance > 0.0) {
      s << ", error tolerance " << error_tolerance << " m, at most " << iterations
        << " iterations per substep";
    } else {
      s << ", " << iterations << " iterations per substep";
    }
    return s.str();
  }
};

enum class Kind { kGround, kSphere, kBox, kSphereAndBox };
const char* kindName(Kind k) {
  switch (k) {
    case Kind::kGround: return "ground";
    case Kind::kSphere: return "sphere";
    case Kind::kBox: return "box";
    case Kind::kSphereAndBox: return "sphere+box";
  }
  return "?";
}

struct Box {
  Vec3 center = Vec3::Zero();
  Vec3 half = Vec3::Ones();
};

struct SceneParams {
  int index = 0;
  int n = 8;              // particles per side
  double size = 1.0;      // m, side length
  double spacing() const { return size / (n - 1); }
  bool drag = false;      // false: dropped; true: row 0 pinned and moved along +y
  Kind kind = Kind::kGround;
  bool has_sphere = false;
  SphereCollider sphere;
  bool sphere_on_ground = false;
  bool has_box = false;
  Box box;
  Vec3 cloth_center = Vec3::Zero();  // centre of the flat starting cloth
  double yaw = 0.0;                  // rad, rotation of the dropped cloth about z
  double drag_distance = 0.0;        // m, travel of the pinned edge along +y
  double duration = 1.5;             // s

  std::string describe() const {
    std::ostringstream s;
    s.precision(4);
    s << "scene " << index << ": " << (drag ? "dragged" : "dropped") << " onto " << kindName(kind)
      << ", grid " << n << "x" << n << ", size " << size << " m (spacing " << spacing()
      << "), cloth centre (" << cloth_center.transpose() << "), yaw " << yaw;
    if (has_sphere)
      s << ", sphere c = (" << sphere.center.transpose() << ") r = " << sphere.radius << " ("
        << sphere.radius / spacing() << " spacings, " << (sphere_on_ground ? "on ground" : "floating")
        << ")";
    if (has_box)
      s << ", box c = (" << box.center.transpose() << ") half = (" << box.half.transpose() << ") ("
        << (box.half / spacing()).transpose() << " spacings)";
    if (drag) s << ", pinned row 0 dragged " << drag_distance << " m along +y";
    s << ", " << duration << " s";
    return s.str();
  }
};

/// A closed box of 12 triangles (outward normals), in world coordinates.
TriangleMesh boxMesh(const Box& b) {
  TriangleMesh m;
  m.vertices.resize(3, 8);
  for (int i = 0; i < 8; ++i) {
    const Vec3 sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    m.vertices.col(i) = b.center + sign.cwiseProduct(b.half);
  }
  m.triangles.resize(3, 12);
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    m.triangles.col(2 * f) << faces[f][0], faces[f][1], faces[f][2];
    m.triangles.col(2 * f + 1) << faces[f][0], faces[f][2], faces[f][3];
  }
  return m;
}

SceneParams generate(std::mt19937& rng, int index) {
  auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  SceneParams p;
  p.index = index;
  p.n = std::uniform_int_distribution<int>(8, 24)(rng);
  p.size = u(0.4, 1.2);
  const double s = p.spacing();
  p.drag = u(0, 1) < 0.3;
  const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
  p.kind = kind == 0 ? Kind::kGround : kind <= 4 ? Kind::kSphere : kind <= 8 ? Kind::kBox
                                                                              : Kind::kSphereAndBox;
  p.has_sphere = p.kind == Kind::kSphere || p.kind == Kind::kSphereAndBox;
  p.has_box = p.kind == Kind::kBox || p.kind == Kind::kSphereAndBox;
  p.duration = u(1.5, 2.0);
  double top = 0.0, extent_y = 0.0;  // highest collider point, half-extent along y
  const double spread = 0.25 * p.size;
  if (p.has_box) {
    p.box.half = Vec3(u(1, 10) * s, u(1, 10) * s, u(1, 10) * s);
    p.box.center = Vec3(u(-spread, spread), u(-spread, spread), p.box.half.z());
    top = std::max(top, 2 * p.box.half.z());
    extent_y = std::max(extent_y, p.box.half.y() + std::abs(p.box.center.y()));
  }
  if (p.has_sphere) {
    const double r = u(1, 10) * s;
    p.sphere_on_ground = p.has_box || u(0, 1) < 0.6;
    double z = p.sphere_on_ground ? r : r + u(0.05, 0.3);
    double x = u(-spread, spread), y = u(-spread, spread);
    if (p.has_box) {  // beside the box, on the ground
      x = p.box.center.x() + p.box.half.x() + r + u(0.0, 2 * s);
      y = p.box.center.y() + u(-p.box.half.y(), p.box.half.y());
    }
    p.sphere.center = Vec3(x, y, z);
    p.sphere.radius = r;
    p.sphere.friction = 0.3;
    top = std::max(top, z + r);
    extent_y = std::max(extent_y, r + std::abs(y));
  }
  if (p.drag) {
    // Row 0 (the edge at local +y) pinned a few cm above the colliders; the sheet lies towards -y
    // and falls, then the edge is dragged along +y across the colliders.
    const double edge_z = top + u(0.03, 0.3);
    const double edge_y = -extent_y - u(0.03, 0.15);
    p.cloth_center = Vec3(u(-spread, spread) * 0.5, edge_y - p.size / 2, edge_z);
    p.drag_distance = 2 * extent_y + u(0.1, 0.5);
  } else {
    p.cloth_center = Vec3(u(-spread, spread), u(-spread, spread), top + u(0.03, 0.5));
    p.yaw = u(-0.5, 0.5);
  }
  return p;
}

struct Outcome {
  double max_strain = 0.0;
  std::string strain_where;    // the most strained structural spring
  double max_strain_all = 0.0; // over every family (information only)
  double worst_inside = 0.0;   // m, deepest particle penetration (positive = inside)
  std::string inside_where;
  double worst_segment = 0.0;  // m, deepest spring excess penetration beyond its allowance
  std::string segment_where;
  int rolled_back = 0;         // steps the simulation rolled back (diverged / non-finite)
  double seconds = 0.0;
};

/// Penetration depth of @p x into the box (> 0 inside): min distance to a face.
double boxDepth(const Box& b, const Vec3& x) {
  const Vec3 d = b.half - (x - b.center).cwiseAbs();
  return d.minCoeff();
}

/// Deepest point of segment a-b in the sphere: r - distance(segment, centre).
double sphereSegmentDepth(const SphereCollider& s, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(ab.dot(s.center - a) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return s.radius - (a + t * ab - s.center).norm();
}

/// Deepest point of segment a-b in the box, sampled (64 samples + ends).
double boxSegmentDepth(const Box& box, const Vec3& a, const Vec3& b) {
  double deepest = -1e300;
  for (int k = 0; k <= 64; ++k) deepest = std::max(deepest, boxDepth(box, a + (b - a) * (k / 64.0)));
  return deepest;
}

Outcome runScene(const SceneParams& p, const Config& c) {
  const auto t0 = std::chrono::steady_clock::now();
  GridSpec g;
  g.rows = g.cols = p.n;
  g.width = g.height = p.size;
  g.material.areal_density = 0.2;
  g.material.structural = 400;
  g.material.shear = 40;
  g.material.has_bending = true;
  g.material.bending = 4;
  g.pose = Eigen::Translation3d(p.cloth_center) * Eigen::AngleAxisd(p.yaw, Vec3::UnitZ());
  BuiltObject obj = buildGrid(g);
  obj.model.damping = 0.1;
  PinSet pins;
  std::vector<int> pin_ids;
  if (p.drag) {
    for (int col = 0; col < p.n; ++col) {
      const int v = gridVertex(0, col, p.n);
      pin_ids.push_back(pins.add(v, obj.rest_positions.col(v), 0.0, obj.model.particleCount()));
    }
  }
  Colliders colliders;
  if (p.has_sphere) colliders.addSphere(p.sphere);
  if (p.has_box)
    colliders.addMesh(std::make_shared<const MeshObstacle>(boxMesh(p.box), kBoxThickness, 0.3));
  colliders.setGround(GroundPlane{true, 0.0, 0.5});
  SimulationOptions opt;
  opt.solver = c.solver;
  opt.settings.max_iterations = c.iterations;
  opt.settings.integrator = c.integrator;
  opt.settings.error_tolerance = c.error_tolerance;
  // Fixed substeps run as frames of their own (the drag moves at each); automatic substeps in
  // frames of 1/60 s, the drag's end-of-frame target reached linearly across them (FrameInputs).
  const int steps_per_frame = std::max(1, c.substeps);
  opt.settings.substeps = c.substeps == 0 ? 0 : 1;
  opt.frame_time = kFrame / steps_per_frame;
  const Points rest = obj.rest_positions;
  Simulation sim(std::move(obj.model), rest, std::move(pins), std::move(colliders), opt);

  Outcome out;
  const int frames = static_cast<int>(std::lround(p.duration / kFrame));
  const double drag_time = 0.7 * p.duration;  // the edge moves at constant speed, then holds
  const double h = kFrame / steps_per_frame;
  for (int f = 0; f < frames; ++f) {
    for (int k = 0; k < steps_per_frame; ++k) {
      if (p.drag) {
        const double t = (f * steps_per_frame + k + 1) * h;
        const double shift = p.drag_distance * std::min(1.0, t / drag_time);
        for (int col = 0; col < p.n; ++col) {
          const int v = gridVertex(0, col, p.n);
          sim.movePin(pin_ids[col], Vec3(rest.col(v)) + Vec3(0, shift, 0));
        }
      }
      const StepReport rep = sim.step();
      if (rep.status != StepStatus::kOk) ++out.rolled_back;
    }
  }

  const Points& x = sim.state().positions;
  const Model& m = sim.model();
  auto where = [&](const char* what, int i, int j) {
    std::ostringstream w;
    w.precision(4);
    w << what << " particle " << i << " (row " << i / p.n << ", col " << i % p.n << ") at ("
      << x.col(i).transpose() << ")";
    if (j >= 0)
      w << " - particle " << j << " (row " << j / p.n << ", col " << j % p.n << ") at ("
        << x.col(j).transpose() << ")";
    return w.str();
  };
  out.worst_inside = -1e300;
  out.worst_segment = -1e300;
  for (int i = 0; i < m.particleCount(); ++i) {
    const Vec3 xi = x.col(i);
    auto note = [&](double depth, const char* what) {
      if (depth > out.worst_inside) { out.worst_inside = depth; out.inside_where = where(what, i, -1); }
    };
    note(-xi.z(), "ground:");
    if (p.has_sphere) note(p.sphere.radius - (xi - p.sphere.center).norm(), "sphere:");
    if (p.has_box) note(boxDepth(p.box, xi), "box:");
  }
  for (std::size_t k = 0; k < m.springs.size(); ++k) {
    const int i = m.springs.first[k], j = m.springs.second[k];
    const Vec3 a = x.col(i), b = x.col(j);
    const double r = m.springs.rest_length[k];
    const double strain = std::abs((a - b).norm() - r) / r;
    out.max_strain_all = std::max(out.max_strain_all, strain);
    if (m.springs.family[k] == SpringFamily::kStructural && strain > out.max_strain) {
      out.max_strain = strain;
      out.strain_where = where(springFamilyName(m.springs.family[k]), i, j);
    }
    if (m.springs.family[k] == SpringFamily::kBending) continue;
    const double l = 1.5 * r;  // chord allowance: see the file comment
    if (p.has_sphere) {
      const double R = p.sphere.radius;
      const double allow = l < 2 * R ? R - std::sqrt(R * R - l * l / 4) : R;
      const double excess = sphereSegmentDepth(p.sphere, a, b) - allow;
      if (excess > out.worst_segment) { out.worst_segment = excess; out.segment_where = where("sphere: spring", i, j); }
    }
    if (p.has_box) {
      const double excess = boxSegmentDepth(p.box, a, b) - l / (2 * std::sqrt(2.0));
      if (excess > out.worst_segment) { out.worst_segment = excess; out.segment_where = where("box: spring", i, j); }
    }
  }
  if (out.segment_where.empty()) { out.worst_segment = 0.0; out.segment_where = "no collider but the ground"; }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

TEST(ContactRandom, ClothOnBallsBoxesAndGroundStaysOutsideAndUntorn) {
  Config c;
  c.substeps = envInt("CONTACT_RANDOM_SUBSTEPS", kDefaultSubsteps);
  c.iterations = envInt("CONTACT_RANDOM_ITERATIONS", kDefaultIterations);
  c.solver = envString("CONTACT_RANDOM_SOLVER", kDefaultSolver);
  c.integrator = integratorFromName(envString("CONTACT_RANDOM_INTEGRATOR", "implicit_euler"));
  c.error_tolerance = std::atof(envString("CONTACT_RANDOM_ERROR_TOLERANCE", "0").c_str());
  const int scenes = envInt("CONTACT_RANDOM_SCENES", kDefaultScenes);
  const unsigned seed = static_cast<unsigned>(envInt("CONTACT_RANDOM_SEED", kDefaultSeed));
  const bool report = envInt("CONTACT_RANDOM_REPORT", 0) != 0;
  // CONTACT_RANDOM_ONLY=3,14: run only these scenes (same parameters: all are generated).
  const std::string only_list = envString("CONTACT_RANDOM_ONLY", "");
  const std::string only = only_list.empty() ? "" : "," + only_list + ",";
  Config ref;
  ref.substeps = envInt("CONTACT_RANDOM_REF_SUBSTEPS", kRefSubsteps);
  ref.iterations = envInt("CONTACT_RANDOM_REF_ITERATIONS", kRefIterations);
  ref.solver = "local_global";
  ref.integrator = integratorFromName(envString("CONTACT_RANDOM_REF_INTEGRATOR", "implicit_euler"));
  std::printf("seed %u, %d scenes, under test: %s; reference: %s\n", seed, scenes,
              c.describe().c_str(), ref.describe().c_str());

  std::mt19937 rng(seed);
  int fail_a = 0, fail_b = 0, fail_c = 0, failed = 0, ran = 0;
  double time_test = 0, time_ref = 0;
  for (int i = 0; i < scenes; ++i) {
    const SceneParams p = generate(rng, i);
    if (!only.empty() && only.find("," + std::to_string(i) + ",") == std::string::npos) continue;
    ++ran;
    const Outcome o = runScene(p, c);
    // Deterministic: the reference configuration is its own reference (no second run).
    const bool same = c.substeps == ref.substeps && c.iterations == ref.iterations &&
                      c.solver == ref.solver && c.integrator == ref.integrator &&
                      c.error_tolerance == ref.error_tolerance;
    const Outcome r = same ? o : runScene(p, ref);
    time_test += o.seconds;
    if (!same) time_ref += r.seconds;
    const double strain_limit = std::max(2 * r.max_strain, r.max_strain + 0.05);
    const bool a = o.worst_inside <= kTol;
    const bool b = o.worst_segment <= kTol;
    const bool cc = o.max_strain <= strain_limit;
    fail_a += !a;
    fail_b += !b;
    fail_c += !cc;
    failed += !(a && b && cc);
    std::ostringstream msg;
    msg.precision(4);
    msg << p.describe() << "\n   " << (a ? "ok  " : "FAIL") << " (a) deepest particle " << o.worst_inside
        << " m [" << o.inside_where << "]\n   " << (b ? "ok  " : "FAIL") << " (b) deepest spring excess "
        << o.worst_segment << " m [" << o.segment_where << "]\n   " << (cc ? "ok  " : "FAIL")
        << " (c) max strain " << o.max_strain << " vs reference " << r.max_strain << " (limit "
        << strain_limit << ") [" << o.strain_where << "], all families " << o.max_strain_all << " vs "
        << r.max_strain_all << (o.rolled_back ? ", steps rolled back: " : "")
        << (o.rolled_back ? std::to_string(o.rolled_back) : std::string())
        << "; reference (a) " << r.worst_inside << " (b) " << r.worst_segment << " (c) ["
        << r.strain_where << "]"
        << "; " << o.seconds << " s + reference " << r.seconds << " s";
    if (report) {
      std::printf("%s%s\n", (a && b && cc) ? "" : "** ", msg.str().c_str());
    } else {
      EXPECT_TRUE(a && b && cc) << "seed " << seed << ", " << c.describe() << "\n" << msg.str();
    }
  }
  std::printf("%s: %d of %d scenes fail (a: %d, b: %d, c: %d); %.1f s under test, %.1f s reference\n",
              c.describe().c_str(), failed, ran, fail_a, fail_b, fail_c, time_test, time_ref);
}

}  // namespace
}  // namespace cloth_sim
