#include "peers.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "accuracy.h"
#include "cases.h"
#include "distances.h"
#include "stats.h"

#ifdef CLOTH_SIM_HAVE_BULLET
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <LinearMath/btScalar.h>
#include <btBulletDynamicsCommon.h>
#endif

namespace cloth_sim::bench {

#ifdef CLOTH_SIM_HAVE_BULLET
namespace {

/// cloth_sim's springs as one Bullet force. Bullet's btDeformableMassSpringForce has one elastic
/// stiffness for every link (and one for links flagged as bending), N/m, not divided by the
/// rest length: force k (|d| - r) d / |d|, exactly cloth_sim's Hooke spring. cloth_sim has three
/// families (structural, shear, bending) with their own stiffness, so this force is Bullet's own
/// mass-spring force (the same elastic force and Hessian, the same code) with the stiffness read
/// per link. Bullet's link damping (along the links' relative velocity) is not cloth_sim's
/// model: it is left out (the drag is applied as cloth_sim applies it, see stepBullet). The
/// type stays BT_MASSSPRING_FORCE: Bullet keeps one force per type.
class ClothSpringForce : public btDeformableMassSpringForce {
 public:
  /// @p clamped: a diagnostic, not Bullet's method: the Hessian's (1 - r / l) term clamped at
  /// 0 (positive semi-definite, as Newton solvers on mass-spring systems commonly project it).
  ClothSpringForce(std::vector<btScalar> stiffness, bool clamped)
      : btDeformableMassSpringForce(0, 0, true), k_(std::move(stiffness)), clamped_(clamped) {}

  void addScaledDampingForce(btScalar, TVStack&) override {}
  void addScaledDampingForceDifferential(btScalar, const TVStack&, TVStack&) override {}
  void buildDampingForceDifferentialDiagonal(btScalar, TVStack&) override {}
  double totalDampingEnergy(btScalar) override { return 0.0; }

  // Bullet's elastic force and its differential (btDeformableMassSpringForce), per-link k.
  void addScaledElasticForce(btScalar scale, TVStack& force) override {
    for (int i = 0; i < m_softBodies.size(); ++i) {
      const btSoftBody* psb = m_softBodies[i];
      for (int j = 0; j < psb->m_links.size(); ++j) {
        const btSoftBody::Link& link = psb->m_links[j];
        const btVector3 dir = link.m_n[1]->m_q - link.m_n[0]->m_q;
        const btVector3 unit = dir.norm() > SIMD_EPSILON ? dir.normalized() : btVector3(0, 0, 0);
        const btVector3 f = scale * k_[j] * (dir - unit * link.m_rl);
        force[link.m_n[0]->index] += f;
        force[link.m_n[1]->index] -= f;
      }
    }
  }

  void addScaledElasticForceDifferential(btScalar scale, const TVStack& dx, TVStack& df) override {
    for (int i = 0; i < m_softBodies.size(); ++i) {
      const btSoftBody* psb = m_softBodies[i];
      for (int j = 0; j < psb->m_links.size(); ++j) {
        const btSoftBody::Link& link = psb->m_links[j];
        const int id1 = link.m_n[0]->index, id2 = link.m_n[1]->index;
        const btVector3 dir = link.m_n[0]->m_q - link.m_n[1]->m_q;
        const btScalar length = dir.norm();
        if (length <= SIMD_EPSILON) continue;
        const btVector3 unit = dir / length;
        const btVector3 dx_diff = dx[id1] - dx[id2];
        const btScalar k = scale * k_[j];
        btScalar stretch = (length - link.m_rl) / length;
        if (clamped_ && stretch < 0) stretch = 0;
        btVector3 f = -k * unit.dot(dx_diff) * unit;
        f += k * unit.dot(dx_diff) * stretch * unit;
        f -= k * stretch * dx_diff;
        df[id1] += f;
        df[id2] -= f;
      }
    }
  }

  double totalElasticEnergy(btScalar) override {
    double energy = 0.0;
    for (int i = 0; i < m_softBodies.size(); ++i) {
      const btSoftBody* psb = m_softBodies[i];
      for (int j = 0; j < psb->m_links.size(); ++j) {
        const btSoftBody::Link& link = psb->m_links[j];
        const double stretch = (link.m_n[1]->m_q - link.m_n[0]->m_q).norm() - link.m_rl;
        energy += 0.5 * k_[j] * stretch * stretch;
      }
    }
    return energy;
  }

 private:
  std::vector<btScalar> k_;  ///< N/m, per link (link j = cloth_sim spring j)
  bool clamped_ = false;
};

/// Bullet's deformable solver with its Newton and Krylov settings reachable (protected there).
class TunableDeformableSolver : public btDeformableBodySolver {
 public:
  void tune(const BulletSettings& s) {
    if (s.newton_iterations > 0) m_maxNewtonIterations = s.newton_iterations;
    if (s.newton_tolerance > 0.0) m_newtonTolerance = s.newton_tolerance;
    if (s.krylov_iterations > 0) {
      m_cg.m_maxIterations = s.krylov_iterations;
      m_cr.m_maxIterations = s.krylov_iterations;
    }
  }
  int newtonIterations() const { return m_maxNewtonIterations; }
  double newtonTolerance() const { return m_newtonTolerance; }
  int krylovIterations() const { return m_useProjection ? m_cg.m_maxIterations : m_cr.m_maxIterations; }
};

/// One Bullet world holding one cloth; members in construction order (destroyed in reverse).
struct BulletCloth {
  std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> configuration;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<TunableDeformableSolver> solver;
  std::unique_ptr<btDeformableMultiBodyConstraintSolver> constraint_solver;
  std::unique_ptr<btDeformableMultiBodyDynamicsWorld> world;
  std::unique_ptr<ClothSpringForce> springs;
  std::unique_ptr<btDeformableGravityForce> gravity;
  std::unique_ptr<btSoftBody> body;
  double damping = 0.0;  ///< 1/s, Model::damping

  ~BulletCloth() {
    if (world && body) world->removeSoftBody(body.get());
  }
};

btVector3 toBt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

/// The cloth of @p sim in Bullet: node i = particle i (its position, velocity and lumped mass;
/// a hard pin: mass 0, which Bullet keeps fixed), link s = spring s (its particles, rest length
/// and stiffness), face t = triangle t (the scene's own triangulation: Bullet's forces do not
/// use faces, only its collision and drawing would), gravity as Bullet's gravity force.
std::unique_ptr<BulletCloth> buildBullet(const Simulation& sim, const BulletSettings& settings) {
  const Model& model = sim.model();
  const State& state = sim.state();
  const int n = model.particleCount();
  std::vector<char> held(static_cast<std::size_t>(n), 0);
  for (const Pin& pin : sim.pins().pins()) {
    if (!pin.isHard()) throw std::runtime_error("peers: soft pins are not mapped to Bullet");
    if ((pin.target - state.positions.col(pin.vertex)).norm() > 1e-12) {
      throw std::runtime_error("peers: a pin away from its particle is not mapped to Bullet");
    }
    held[pin.vertex] = 1;
  }

  auto c = std::make_unique<BulletCloth>();
  c->configuration = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  c->dispatcher = std::make_unique<btCollisionDispatcher>(c->configuration.get());
  c->broadphase = std::make_unique<btDbvtBroadphase>();
  c->solver = std::make_unique<TunableDeformableSolver>();
  c->constraint_solver = std::make_unique<btDeformableMultiBodyConstraintSolver>();
  c->constraint_solver->setDeformableSolver(c->solver.get());
  c->world = std::make_unique<btDeformableMultiBodyDynamicsWorld>(
      c->dispatcher.get(), c->broadphase.get(), c->constraint_solver.get(),
      c->configuration.get(), c->solver.get());
  c->world->setGravity(toBt(model.gravity));
  c->world->getWorldInfo().m_gravity = toBt(model.gravity);
  c->world->setImplicit(true);
  c->world->setLineSearch(settings.line_search);
  c->world->setUseProjection(settings.projection);
  c->solver->m_useProjection = settings.projection;
  c->solver->tune(settings);

  std::vector<btVector3> x(static_cast<std::size_t>(n));
  std::vector<btScalar> m(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    x[i] = toBt(state.positions.col(i));
    m[i] = held[i] ? 0.0 : model.mass[i];  // Bullet: mass 0 = inverse mass 0 = fixed
  }
  c->body = std::make_unique<btSoftBody>(&c->world->getWorldInfo(), n, x.data(), m.data());
  btSoftBody& body = *c->body;
  for (int i = 0; i < n; ++i) {
    body.m_nodes[i].m_v = toBt(state.velocities.col(i));
    body.m_nodes[i].m_vn = body.m_nodes[i].m_v;
  }
  const Springs& springs = model.springs;
  std::vector<btScalar> stiffness(springs.size());
  for (std::size_t s = 0; s < springs.size(); ++s) {
    body.appendLink(springs.first[s], springs.second[s], nullptr, false);
    stiffness[s] = springs.stiffness[s];
  }
  for (Eigen::Index t = 0; t < model.triangles.cols(); ++t) {
    body.appendFace(model.triangles(0, t), model.triangles(1, t), model.triangles(2, t));
  }
  // updateConstants() resets every link's rest length to its current length; run it now, then
  // set cloth_sim's rest lengths, and keep Bullet from running it again at its first step.
  body.updateConstants();
  for (std::size_t s = 0; s < springs.size(); ++s) {
    btSoftBody::Link& link = body.m_links[static_cast<int>(s)];
    link.m_rl = springs.rest_length[s];
    link.m_c1 = link.m_rl * link.m_rl;
    link.m_bbending = 0;
  }
  body.m_bUpdateRtCst = false;
  body.m_cfg.collisions = 0;  // no colliders in the covered scenes, no self-collision
  body.m_cfg.drag = 0;        // Bullet's own air drag (a velocity scale per step): the drag is ours
  body.setSelfCollision(false);
  body.setActivationState(DISABLE_DEACTIVATION);  // a cloth at rest must not fall asleep
  c->world->addSoftBody(&body);

  c->springs = std::make_unique<ClothSpringForce>(std::move(stiffness), settings.clamped_hessian);
  c->damping = model.damping;
  c->world->addForce(&body, c->springs.get());
  c->gravity = std::make_unique<btDeformableGravityForce>(toBt(model.gravity));
  c->world->addForce(&body, c->gravity.get());
  return c;
}

/// One implicit step of @p h. The drag is applied as cloth_sim applies it (docs/method.md, "The
/// model"): v <- exp(-gamma h) v before the step, exactly, outside the solve (Bullet's implicit
/// step starts from the nodes' m_vn; its own air drag, m_cfg.drag, only scales the explicit
/// prediction, the Newton iterations' start). Inside Bullet the drag would be implicit,
/// v (1 + gamma h): that differs from cloth_sim's by gamma h^2 g per step, first order in h
/// (1e-4 m after 0.25 s on hanging at 8 x 8, h = 1/240 s, measured).
void stepBullet(BulletCloth& c, btScalar h) {
  if (c.damping > 0.0) {
    const btScalar scale = std::exp(-c.damping * h);
    for (int i = 0; i < c.body->m_nodes.size(); ++i) {
      btSoftBody::Node& node = c.body->m_nodes[i];
      node.m_v *= scale;
      node.m_vn *= scale;
    }
  }
  c.world->stepSimulation(h, 0);  // variable step: one internal step of exactly h
}

void readState(const btSoftBody& body, Points& x, Points& v) {
  const int n = body.m_nodes.size();
  x.resize(3, n);
  v.resize(3, n);
  for (int i = 0; i < n; ++i) {
    const btSoftBody::Node& node = body.m_nodes[i];
    x.col(i) = Vec3(node.m_x.x(), node.m_x.y(), node.m_x.z());
    v.col(i) = Vec3(node.m_v.x(), node.m_v.y(), node.m_v.z());
  }
}

}  // namespace

std::string bulletBuild() {
  char text[64];
  std::snprintf(text, sizeof text, "Bullet %d.%02d (%s precision)", btGetVersion() / 100,
                btGetVersion() % 100, sizeof(btScalar) == 8 ? "double" : "single");
  return text;
}

PeerRun runBullet(const SceneConfig& scene, const BulletSettings& settings,
                  const std::vector<int>& sample_frames, double max_frame_ms) {
  if (!scene.spheres.empty() || !scene.meshes.empty() || !scene.bodies.empty() ||
      scene.ground.enabled) {
    throw std::runtime_error("peers: " + scene.name + " has colliders, not mapped to Bullet");
  }
  const Simulation sim = makeSimulation(scene);
  std::unique_ptr<BulletCloth> cloth = buildBullet(sim, settings);
  PeerRun run;
  run.newton_iterations = cloth->solver->newtonIterations();
  run.newton_tolerance = cloth->solver->newtonTolerance();
  run.krylov_iterations = cloth->solver->krylovIterations();
  const btScalar h = scene.time_step / settings.substeps;
  std::size_t next = 0;
  for (int f = 1; next < sample_frames.size(); ++f) {
    const double start = now(), cpu_start = threadCpuNow();
    for (int s = 0; s < settings.substeps; ++s) stepBullet(*cloth, h);
    run.frame_ms.push_back(1e3 * (now() - start));
    run.frame_cpu_ms.push_back(1e3 * (threadCpuNow() - cpu_start));
    if (f == sample_frames[next]) {
      Points x, v;
      readState(*cloth->body, x, v);
      run.finite = run.finite && x.allFinite();
      run.positions.push_back(x);
      run.velocities.push_back(v);
      ++next;
    }
    if (f == 5 && median(run.frame_cpu_ms) > max_frame_ms) {
      run.stopped = true;
      break;
    }
  }
  return run;
}

#else  // no Bullet

std::string bulletBuild() { return ""; }

PeerRun runBullet(const SceneConfig&, const BulletSettings&, const std::vector<int>&, double) {
  throw std::runtime_error("peers: cloth_sim_bench was built without Bullet (libbullet-dev)");
}

#endif

void runPeers(const PeersOptions& o) {
  const std::string build = bulletBuild();
  if (build.empty()) {
    std::printf("peers: Bullet is absent (cloth_sim_bench was built without libbullet-dev); "
                "nothing to run\n");
    return;
  }
  std::printf("peers: %s, implicit (backward Euler, Newton + %s)\n", build.c_str(),
              o.projection ? "CG, projection mode"
                           : "conjugate residual, Lagrange multiplier mode");
  std::filesystem::create_directories(o.out_dir);
  std::ofstream csv(o.out_dir + "/peers.csv");
  csv << "case,solver,substeps,iterations,time,rms_error,max_error,com_error,energy_ratio,mean_strain,"
         "max_strain,ref_mean_strain,ref_max_strain,frame_ms_median,frame_ms_p10,frame_ms_p90,"
         "rollbacks,status,cpu_ms_median,cpu_ms_p10,cpu_ms_p90,error_tolerance,mean_substeps,"
         "estimate_sum,newton_tolerance,krylov_iterations,floor_rms,peer\n";
  AccuracyOptions ao;
  ao.cache_dir = o.cache_dir;
  ao.reference = o.reference;
  ao.reference_substeps = o.reference_substeps;
  for (const std::string& scene_name : o.scenes) {
    const bool shipped = std::filesystem::exists(o.scenes_dir + "/" + scene_name + ".yaml");
    const std::string dir = shipped || o.untuned_dir.empty() ? o.scenes_dir : o.untuned_dir;
    for (int grid : o.grids) {
      const BenchCase c = makeCase(dir, scene_name, grid);
      std::fprintf(stderr, "%s: reference...\n", c.name.c_str());
      const TrueMotion truth = trueMotion(c.config, c.name, o.times, ao);
      Simulation probe = makeSimulation(c.config);
      const Eigen::VectorXd mass = probe.model().mass;
      std::printf("%s: %d particles, %zu springs, reference %s h = 1/%.0f s, diagonal %.3f m\n",
                  c.name.c_str(), probe.model().particleCount(), probe.model().springs.size(),
                  truth.kind.c_str(), 1.0 / truth.h, truth.diagonal);
      for (int newton : o.newton_iterations) {
        for (int substeps : o.substeps) {
          BulletSettings settings;
          settings.substeps = substeps;
          settings.newton_iterations = newton;
          settings.newton_tolerance = o.newton_tolerance;
          settings.krylov_iterations = o.krylov_iterations;
          settings.projection = o.projection;
          settings.line_search = o.line_search;
          settings.clamped_hessian = o.clamped_hessian;
          const PeerRun run = runBullet(c.config, settings, truth.frames, o.max_frame_ms);
          std::string label =
              newton > 0 ? "bullet/newton" + std::to_string(newton) : std::string("bullet");
          if (o.line_search) label += "+ls";
          if (o.clamped_hessian) label += "+psd";
          const std::string status = run.stopped ? "too_slow" : run.finite ? "ok" : "diverged";
          std::printf("  %-16s %3d substeps: %8.3f ms per frame (CPU %.3f)", label.c_str(),
                      substeps, median(run.frame_ms), median(run.frame_cpu_ms));
          for (std::size_t k = 0; k < run.positions.size(); ++k) {
            const double error = rms(run.positions[k], truth.positions[k]) / truth.diagonal;
            std::printf("  %.2f s: %.3g %%", o.times[k], 100.0 * error);

            SimulationSnapshot snap = probe.snapshot();
            snap.state.positions = run.positions[k];
            snap.state.velocities = run.velocities[k];
            probe.restore(snap);
            const auto [mean_strain, max_strain] = springStrain(probe.model().springs, run.positions[k]);
            csv << c.name << ',' << label << ',' << substeps << ',' << run.newton_iterations << ','
                << o.times[k] << ',' << error << ','
                << maxDistance(run.positions[k], truth.positions[k]) / truth.diagonal << ','
                << centerOfMassDistance(run.positions[k], truth.positions[k], mass) / truth.diagonal
                << ',' << probe.totalEnergy() / truth.energy[k] << ',' << mean_strain << ','
                << max_strain << ',' << truth.mean_strain[k] << ',' << truth.max_strain[k] << ','
                << median(run.frame_ms) << ',' << quantile(run.frame_ms, 0.1) << ','
                << quantile(run.frame_ms, 0.9) << ",0," << status << ','
                << median(run.frame_cpu_ms) << ',' << quantile(run.frame_cpu_ms, 0.1) << ','
                << quantile(run.frame_cpu_ms, 0.9) << ",0," << substeps << ",0,"
                << run.newton_tolerance << ',' << run.krylov_iterations << ','
                << rms(truth.coarse[k], truth.positions[k]) / truth.diagonal << ','
                << build << '\n';
          }
          if (run.positions.empty()) {
            csv << c.name << ',' << label << ',' << substeps << ',' << run.newton_iterations
                << ",,,,,,,,,," << median(run.frame_ms) << ",,,0," << status << ','
                << median(run.frame_cpu_ms) << ",,,0," << substeps << ",0,"
                << run.newton_tolerance << ',' << run.krylov_iterations << ",," << build << '\n';
          }
          std::printf("  [%s]\n", status.c_str());
          std::fflush(stdout);
          csv.flush();
        }
      }
    }
  }
  std::printf("peers: wrote %s/peers.csv\n", o.out_dir.c_str());
}

}  // namespace cloth_sim::bench
