#include "accuracy.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "cases.h"
#include "distances.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/registry.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

/// What a run looks like at one sample time.
struct Sample {
  Points positions;
  double energy = 0.0;       ///< J, Simulation::totalEnergy
  double mean_strain = 0.0;  ///< mean |l - r| / r over the springs
  double max_strain = 0.0;
};

struct Trajectory {
  std::vector<Sample> samples;      ///< one per sample frame (fewer when stopped early)
  std::vector<double> frame_ms;     ///< wall time of every frame
  std::vector<double> frame_cpu_ms; ///< CPU time of every frame (this thread)
  int rollbacks = 0;                ///< steps the simulation rolled back
  bool stopped = false;             ///< slower than max_frame_ms: not run to the end
  double substeps_sum = 0.0;        ///< substeps of all frames (their mean: the cost)
  double estimate_sum = 0.0;        ///< m, the frames' error estimates, summed
};

/// One configuration of the sweep.
struct Config {
  std::string solver;
  int substeps = 1;
  int iterations = 1;
  double tolerance = 0.0;
  Integrator integrator = Integrator::kImplicitEuler;
  bool warm = false;  ///< SolverSettings::warm_start
  double error_tolerance = 0.0;  ///< m per frame; > 0: substeps 0 (chosen by the estimate)
  /// The scene format's default as a user gets it (no solver block: error control, BDF2, a
  /// tolerance of kDefaultRelativeErrorTolerance x the cloth's size); labelled "default".
  bool scene_default = false;
  /// With scene_default: run it with `integrator` instead of the format's (a scene that
  /// gives only solver.integrator), to compare.
  bool default_integrator = false;
  bool errorControlled() const { return scene_default || error_tolerance > 0.0; }
  /// The solver column: "local_global", "local_global/bdf2", "anderson+warm/bdf2".
  std::string name() const {
    if (scene_default) return "default";
    const std::string base = warm ? solver + "+warm" : solver;
    return integrator == Integrator::kImplicitEuler ? base
                                                    : base + "/" + integratorName(integrator);
  }
  std::string label() const {
    if (scene_default) return name();
    if (error_tolerance > 0.0) {
      char text[32];
      std::snprintf(text, sizeof text, " e%g", error_tolerance);
      return name() + text;
    }
    return name() + " s" + std::to_string(substeps) + " i" +
           (tolerance > 0.0 ? std::string("conv") : std::to_string(iterations));
  }
};

Sample sampleOf(const Simulation& sim) {
  Sample s;
  s.positions = sim.state().positions;
  s.energy = sim.totalEnergy();
  std::tie(s.mean_strain, s.max_strain) = springStrain(sim.model().springs, s.positions);
  return s;
}

/// One frame's local error: the frame run from the configuration's own state, against the
/// true motion from that same state over the same frame.
struct LocalError {
  int frame = 0;
  int substeps = 0;         ///< of that frame
  double estimate = 0.0;    ///< m, StepReport::error_estimate of the frame
  double carried = 0.0;     ///< m, StepReport::carried_iteration_error of the frame
  double truth = 0.0;       ///< m, RMS over the free particles of (frame's result - true motion)
  double reference_error = 0.0;  ///< m, the true motion's own error (see trueFrame)
};

/// Where and how local errors are measured during a run (error-controlled configurations).
struct LocalErrorProbe {
  SceneConfig scene;         ///< the case's scene: the reference simulation is built from it
  std::vector<int> frames;   ///< frames (1-based, increasing) whose local error is measured
  int substeps = 64;         ///< the reference's finer run takes 2 x this substeps
};

/// The motion over one frame from @p sim's current state, as implicit Euler converged
/// (chebyshev, relative change 1e-9) at n and 2n substeps combined by Richardson extrapolation
/// (2 x_2n - x_n, second order); @p own_error gets RMS(x_2n - x_n) (about x_2n's error; the
/// extrapolation's own error was measured 50x below it on flag-32: docs/benchmark.md).
Points trueFrame(const Simulation& sim, Simulation& reference, int n, double& own_error) {
  const auto frame_with = [&](int substeps) {
    SimulationSnapshot snap = sim.snapshot();
    snap.options.solver = "chebyshev";
    SolverSettings& s = snap.options.settings;
    s.substeps = substeps;
    s.max_iterations = 2000;
    s.tolerance = 1e-9;
    s.error_tolerance = 0.0;
    s.integrator = Integrator::kImplicitEuler;
    snap.substeps = substeps;
    snap.state.has_previous = false;
    reference.restore(snap);
    reference.step();
    return Points(reference.state().positions);
  };
  const Points coarse = frame_with(n), fine = frame_with(2 * n);
  own_error = std::sqrt((fine - coarse).colwise().squaredNorm().mean());
  return 2.0 * fine - coarse;
}

/// RMS distance (m) between @p a and @p b over the particles @p sim does not hold by a hard pin.
double freeRms(const Simulation& sim, const Points& a, const Points& b) {
  std::vector<char> held(static_cast<std::size_t>(a.cols()), 0);
  for (const Pin& pin : sim.pins().pins()) {
    if (pin.isHard()) held[pin.vertex] = 1;
  }
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index i = 0; i < a.cols(); ++i) {
    if (held[i]) continue;
    sum += (a.col(i) - b.col(i)).squaredNorm();
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

/// @p scene as it runs under @p config (substeps as the user sets them; a reference finer than
/// that setting allows takes the frame as its step instead, see run()).
SceneConfig configured(SceneConfig scene, const Config& config) {
  if (config.scene_default) {  // as a scene with no solver block
    scene.options.solver = defaultSceneOptions().solver;
    scene.options.settings = defaultSceneOptions().settings;
    scene.given = SolverFieldsGiven{};
    if (config.default_integrator) {
      scene.options.settings.integrator = config.integrator;
      scene.given.integrator = true;
    }
    return scene;
  }
  const bool as_setting = settings::kSubsteps.allows(config.substeps);
  SceneOverrides overrides;
  overrides.substeps = as_setting ? config.substeps : 1;
  if (!as_setting) overrides.time_step = scene.time_step / config.substeps;
  overrides.solver = config.solver;
  overrides.iterations = config.iterations;
  overrides.tolerance = config.tolerance;
  overrides.integrator = config.integrator;
  overrides.warm_start = config.warm;
  overrides.error_tolerance = config.error_tolerance;
  if (config.error_tolerance > 0.0) overrides.substeps = 0;
  return applyOverrides(std::move(scene), overrides);
}

/// Runs @p scene with @p config frame by frame (a frame is the scene's time step) and samples
/// it at the end of the frames in @p sample_frames (increasing). With a @p probe, the local
/// error of the probe's frames is measured too (@p local_errors).
Trajectory run(const SceneConfig& scene, const Config& config,
               const std::vector<int>& sample_frames, double max_frame_ms,
               const LocalErrorProbe* probe = nullptr,
               std::vector<LocalError>* local_errors = nullptr) {
  // Substeps as the user sets them (solver.substeps); a reference finer than that setting
  // allows takes the frame as its step instead (nothing moves kinematically in these scenes).
  const bool as_setting = config.scene_default || settings::kSubsteps.allows(config.substeps);
  const int steps_per_frame = as_setting ? 1 : config.substeps;
  Simulation sim = makeSimulation(configured(scene, config));
  std::optional<Simulation> reference;
  if (probe != nullptr) reference.emplace(makeSimulation(probe->scene));
  std::size_t next = 0, next_probe = 0;
  Trajectory t;
  for (int f = 1; next < sample_frames.size(); ++f) {
    const bool probed = probe != nullptr && next_probe < probe->frames.size() &&
                        probe->frames[next_probe] == f;
    LocalError local;
    Points truth;
    if (probed) truth = trueFrame(sim, *reference, probe->substeps, local.reference_error);
    const double start = now(), cpu_start = threadCpuNow();
    double frame_estimate = 0.0, frame_carried = 0.0;
    int frame_substeps = 0;
    for (int s = 0; s < steps_per_frame; ++s) {
      const StepReport report = sim.step();
      if (report.status != StepStatus::kOk) ++t.rollbacks;
      frame_substeps += report.substeps;
      frame_estimate += report.error_estimate;
      frame_carried += report.carried_iteration_error;
    }
    t.frame_ms.push_back(1e3 * (now() - start));
    t.frame_cpu_ms.push_back(1e3 * (threadCpuNow() - cpu_start));
    t.substeps_sum += frame_substeps;
    t.estimate_sum += frame_estimate;
    if (probed) {
      local.frame = f;
      local.substeps = frame_substeps;
      local.estimate = frame_estimate;
      local.carried = frame_carried;
      local.truth = freeRms(sim, sim.state().positions, truth);
      local_errors->push_back(local);
      ++next_probe;
    }
    if (f == sample_frames[next]) {
      t.samples.push_back(sampleOf(sim));
      ++next;
    }
    if (f == 5 && median(t.frame_cpu_ms) > max_frame_ms) {  // CPU time: not stopped by load
      t.stopped = true;
      break;
    }
  }
  return t;
}

// --- reference cache: the samples of a reference run, keyed by everything that defines it ----
void writeSamples(const std::string& path, const std::vector<Sample>& samples) {
  std::ofstream out(path, std::ios::binary);
  const auto put = [&out](double v) { out.write(reinterpret_cast<const char*>(&v), sizeof v); };
  put(static_cast<double>(samples.size()));
  for (const Sample& s : samples) {
    put(static_cast<double>(s.positions.cols()));
    for (Eigen::Index i = 0; i < s.positions.size(); ++i) put(s.positions.data()[i]);
    put(s.energy);
    put(s.mean_strain);
    put(s.max_strain);
  }
}

bool readSamples(const std::string& path, std::vector<Sample>& samples) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  const auto get = [&in]() {
    double v = 0.0;
    in.read(reinterpret_cast<char*>(&v), sizeof v);
    return v;
  };
  samples.resize(static_cast<std::size_t>(get()));
  for (Sample& s : samples) {
    s.positions.resize(3, static_cast<Eigen::Index>(get()));
    for (Eigen::Index i = 0; i < s.positions.size(); ++i) s.positions.data()[i] = get();
    s.energy = get();
    s.mean_strain = get();
    s.max_strain = get();
  }
  return static_cast<bool>(in);
}

/// "verlet", "implicit" or "bdf2": the reference integrator for @p scene (see AccuracyOptions::reference).
std::string referenceKind(const SceneConfig& scene, const AccuracyOptions& o) {
  if (o.reference != "auto") return o.reference;
  const bool colliders = !scene.spheres.empty() || !scene.meshes.empty() || scene.ground.enabled;
  return colliders ? "bdf2" : "verlet";
}

/// A hash of everything that defines the motion of @p scene's simulation (model, initial
/// state, pins, colliders, frame), and nothing of its solver: the key of a cached reference.
std::size_t motionFingerprint(const SceneConfig& scene) {
  const Simulation sim = makeSimulation(scene);
  std::size_t seed = 0;
  const auto mix = [&seed](double v) {
    seed ^= std::hash<double>{}(v) + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2);
  };
  const Model& m = sim.model();
  for (Eigen::Index i = 0; i < m.mass.size(); ++i) mix(m.mass[i]);
  for (std::size_t k = 0; k < m.springs.size(); ++k) {
    for (double v : {double(m.springs.first[k]), double(m.springs.second[k]),
                     m.springs.rest_length[k], m.springs.stiffness[k]}) {
      mix(v);
    }
  }
  for (Eigen::Index i = 0; i < sim.state().positions.size(); ++i) mix(sim.state().positions.data()[i]);
  for (double v : {m.damping, sim.frameTime(), m.gravity.x(), m.gravity.y(), m.gravity.z()}) mix(v);
  for (const Pin& p : sim.pins().pins()) {
    for (double v : {double(p.vertex), p.target.x(), p.target.y(), p.target.z(), p.stiffness}) mix(v);
  }
  for (const SphereCollider& s : sim.colliders().spheres()) {
    for (double v : {s.center.x(), s.center.y(), s.center.z(), s.radius, s.velocity.x(),
                     s.velocity.y(), s.velocity.z(), s.mass, s.friction, s.restitution}) {
      mix(v);
    }
  }
  const GroundPlane& g = sim.colliders().ground();
  for (double v : {double(g.enabled), g.height, g.friction}) mix(v);
  for (const auto& mesh : sim.colliders().meshes()) {
    for (Eigen::Index i = 0; i < mesh->mesh().vertices.size(); ++i) mix(mesh->mesh().vertices.data()[i]);
    mix(mesh->thickness());
    mix(mesh->friction());
  }
  return seed;
}

/// Reference samples at h = frame / substeps, from the cache when it holds this exact run.
std::vector<Sample> reference(const SceneConfig& scene, const std::string& case_name,
                              int substeps, const std::vector<int>& frames,
                              const AccuracyOptions& o) {
  const std::string kind = referenceKind(scene, o);
  Config config = kind == "verlet" ? Config{"verlet", substeps, 1, 0.0}
                                   : Config{"chebyshev", substeps, 2000, 1e-9};
  if (kind == "bdf2") config.integrator = Integrator::kBdf2;
  std::ostringstream key;
  key << motionFingerprint(scene) << '|' << case_name << '|' << config.label();
  for (int f : frames) key << ',' << f;
  std::string path;
  if (!o.cache_dir.empty()) {
    std::filesystem::create_directories(o.cache_dir);
    path = o.cache_dir + "/accuracy-" + case_name + "-s" + std::to_string(substeps) + "-" +
           std::to_string(std::hash<std::string>{}(key.str())) + ".bin";
    std::vector<Sample> cached;
    if (readSamples(path, cached) && cached.size() == frames.size()) return cached;
  }
  const Trajectory t = run(scene, config, frames, 1e300);
  if (t.rollbacks > 0) {
    throw std::runtime_error(case_name + ": the reference run rolled back " +
                             std::to_string(t.rollbacks) + " steps");
  }
  if (!path.empty()) writeSamples(path, t.samples);
  return t.samples;
}

/// Diagonal of the bounding box of @p x (m): the cloth's size, taken at rest.
double diagonal(const Points& x) { return (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).norm(); }

void progress(int done, int total, const std::string& what) {
  const int width = 30, filled = total > 0 ? width * done / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d %-40.40s", std::string(filled, '#').c_str(),
               std::string(width - filled, '-').c_str(), done, total, what.c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

std::vector<Config> configsFor(const AccuracyOptions& o, int grid) {
  std::vector<Config> configs;
  if (o.scene_default) {
    Config c;
    c.scene_default = true;
    if (!o.default_integrator.empty()) {
      c.integrator = integratorFromName(o.default_integrator);
      c.default_integrator = true;
    }
    configs.push_back(c);
  }
  if (o.default_only) return configs;
  for (const std::string& name : o.integrators) {
    const Integrator integrator = integratorFromName(name);
    for (const std::string& solver : o.solvers) {
      const SolverCapabilities& can = solverEntry(solver).capabilities;
      if (!can.supports(integrator)) continue;  // xpbd: its own scheme only
      if (!can.tolerance) {  // no convergence test: the small-steps way, one sweep per substep
        for (int s : o.xpbd_substeps) configs.push_back({solver, s, 1, 0.0, integrator});
        continue;
      }
      const bool warm = o.warm_start && can.warm_start;
      for (int s : o.substeps) {
        for (int i : o.iterations) configs.push_back({solver, s, i, 0.0, integrator, warm});
      }
    }
    for (const std::string& solver : o.error_control_solvers) {
      if (!solverEntry(solver).capabilities.supports(integrator)) continue;
      for (double tol : o.error_tolerances) {
        Config c{solver, 0, 100, 0.0, integrator};
        c.error_tolerance = tol;
        configs.push_back(c);
      }
    }
    if (grid <= o.newton_max_grid) {
      for (int s : o.substeps) configs.push_back({"newton", s, 100, 1e-10, integrator});
    }
  }
  return configs;
}

}  // namespace

// w_max^2 <= max_i 2 sum_(springs of i) k / m_i (Gershgorin on M^-1 K, K the spring stiffness
// matrix at rest).
int verletSubsteps(const SceneConfig& scene) {
  const Simulation sim = makeSimulation(scene);
  const Model& model = sim.model();
  Eigen::VectorXd stiffness = Eigen::VectorXd::Zero(model.particleCount());
  for (std::size_t k = 0; k < model.springs.size(); ++k) {
    stiffness[model.springs.first[k]] += model.springs.stiffness[k];
    stiffness[model.springs.second[k]] += model.springs.stiffness[k];
  }
  const double omega = std::sqrt((2.0 * stiffness.array() / model.mass.array()).maxCoeff());
  int substeps = 1;
  while (scene.time_step / substeps > 1.0 / omega) substeps *= 2;
  return substeps;
}

TrueMotion trueMotion(const SceneConfig& scene, const std::string& case_name,
                      const std::vector<double>& times, const AccuracyOptions& o) {
  TrueMotion truth;
  const double frame = scene.time_step;
  for (double t : times) truth.frames.push_back(static_cast<int>(std::lround(t / frame)));
  truth.kind = referenceKind(scene, o);
  int substeps = o.reference_substeps;
  if (truth.kind == "verlet") substeps = std::max(substeps, verletSubsteps(scene));
  if (truth.kind == "bdf2") {
    substeps = std::max(substeps, AccuracyOptions::kContactReferenceSubsteps);
  }
  truth.h = frame / (2 * substeps);
  const std::vector<Sample> coarse = reference(scene, case_name, substeps, truth.frames, o);
  const std::vector<Sample> fine = reference(scene, case_name, 2 * substeps, truth.frames, o);
  truth.diagonal = diagonal(makeSimulation(scene).state().positions);
  for (std::size_t k = 0; k < fine.size(); ++k) {
    truth.positions.push_back(fine[k].positions);
    truth.coarse.push_back(coarse[k].positions);
    truth.energy.push_back(fine[k].energy);
    truth.coarse_energy.push_back(coarse[k].energy);
    truth.mean_strain.push_back(fine[k].mean_strain);
    truth.max_strain.push_back(fine[k].max_strain);
  }
  return truth;
}

void runAccuracy(const AccuracyOptions& o) {
  std::filesystem::create_directories(o.out_dir);
  std::ofstream csv(o.out_dir + "/accuracy.csv");
  for (const std::string& name : o.integrators) integratorFromName(name);  // fail before running
  csv << "case,solver,substeps,iterations,time,rms_error,max_error,com_error,energy_ratio,mean_strain,"
         "max_strain,ref_mean_strain,ref_max_strain,frame_ms_median,frame_ms_p10,frame_ms_p90,"
         "rollbacks,status,cpu_ms_median,cpu_ms_p10,cpu_ms_p90,error_tolerance,mean_substeps,"
         "estimate_sum\n";
  std::ofstream local_csv(o.out_dir + "/local_error.csv");
  local_csv << "case,solver,error_tolerance,frame,time,substeps,estimate,true_error,"
               "reference_error,carried_iteration_error\n";
  std::ofstream ref_csv(o.out_dir + "/accuracy_reference.csv");
  ref_csv << "case,particles,diagonal,reference,h_ref,time,floor_rms,floor_max,floor_com,energy,"
             "mean_strain,max_strain,energy_2h\n";

  for (const std::string& scene_name : o.scenes) {
    const bool shipped = std::filesystem::exists(o.scenes_dir + "/" + scene_name + ".yaml");
    const std::string dir = shipped || o.untuned_dir.empty() ? o.scenes_dir : o.untuned_dir;
    const std::string file = dir + "/" + scene_name + ".yaml";
    const bool mesh = loadSceneFile(file).cloth_kind == SceneConfig::ClothKind::kMesh;
    for (int grid : mesh ? std::vector<int>{0} : o.grids) {
      BenchCase c = mesh ? BenchCase{scene_name + "-mesh", scene_name, 0, false, loadSceneFile(file)}
                         : makeCase(dir, scene_name, grid);
      const double frame = c.config.time_step;
      progress(0, 1, c.name + " reference (h and h / 2)");
      const TrueMotion truth = trueMotion(c.config, c.name, o.times, o);
      progress(1, 1, c.name + " reference done");
      const std::vector<int>& frames = truth.frames;
      const std::vector<Points>& ref = truth.positions;
      const double size = truth.diagonal;
      const Eigen::VectorXd mass = makeSimulation(c.config).model().mass;
      for (std::size_t k = 0; k < frames.size(); ++k) {
        ref_csv << c.name << ',' << ref[k].cols() << ',' << size << ',' << truth.kind << ','
                << truth.h << ',' << o.times[k] << ','
                << rms(truth.coarse[k], ref[k]) / size << ','
                << maxDistance(truth.coarse[k], ref[k]) / size << ','
                << centerOfMassDistance(truth.coarse[k], ref[k], mass) / size << ','
                << truth.energy[k] << ',' << truth.mean_strain[k] << ',' << truth.max_strain[k]
                << ',' << truth.coarse_energy[k] << '\n';
      }
      std::printf("%s: %ld particles, diagonal %.3f m, reference %s h = 1/%.0f s; its error "
                  "(distance to h x 2) at t = %g s: %.3g %% RMS\n",
                  c.name.c_str(), static_cast<long>(ref.front().cols()), size,
                  truth.kind.c_str(), 1.0 / truth.h, o.times.front(),
                  100.0 * rms(truth.coarse.front(), ref.front()) / size);

      LocalErrorProbe probe{c.config, {}, o.local_error_substeps};
      const int last = static_cast<int>(std::lround(o.local_error_until / frame));
      for (int k = 1; k <= o.local_error_frames; ++k) {
        probe.frames.push_back(std::max(1, last * k / o.local_error_frames));
      }
      const double default_tolerance = kDefaultRelativeErrorTolerance * size;
      const std::vector<Config> configs = configsFor(o, grid);
      for (std::size_t n = 0; n < configs.size(); ++n) {
        const Config& cfg = configs[n];
        progress(static_cast<int>(n), static_cast<int>(configs.size()), c.name + " " + cfg.label());
        std::vector<LocalError> local;
        const bool probed = cfg.errorControlled() && !probe.frames.empty();
        // The default is what the bars judge: it runs to the end however slow, so that a
        // miss of the frame shows as its time rather than as a missing row.
        const double max_frame_ms =
            cfg.scene_default ? std::numeric_limits<double>::infinity() : o.max_frame_ms;
        const Trajectory t =
            run(c.config, cfg, frames, max_frame_ms, probed ? &probe : nullptr, &local);
        const double tolerance = cfg.scene_default ? default_tolerance : cfg.error_tolerance;
        for (const LocalError& e : local) {
          local_csv << c.name << ',' << cfg.name() << ',' << tolerance << ',' << e.frame << ','
                    << e.frame * frame << ',' << e.substeps << ',' << e.estimate << ','
                    << e.truth << ',' << e.reference_error << ',' << e.carried << '\n';
        }
        local_csv.flush();
        const std::string status = t.stopped ? "too_slow" : t.rollbacks > 0 ? "rolled_back" : "ok";
        for (std::size_t k = 0; k < t.samples.size(); ++k) {
          const Sample& s = t.samples[k];
          csv << c.name << ',' << cfg.name() << ',' << cfg.substeps << ','
              << (cfg.tolerance > 0.0 ? 0 : cfg.iterations) << ',' << o.times[k] << ','
              << rms(s.positions, ref[k]) / size << ','
              << maxDistance(s.positions, ref[k]) / size << ','
              << centerOfMassDistance(s.positions, ref[k], mass) / size << ','
              << s.energy / truth.energy[k] << ',' << s.mean_strain << ',' << s.max_strain << ','
              << truth.mean_strain[k] << ',' << truth.max_strain[k] << ',' << median(t.frame_ms)
              << ',' << quantile(t.frame_ms, 0.1) << ',' << quantile(t.frame_ms, 0.9) << ','
              << t.rollbacks << ',' << status << ',' << median(t.frame_cpu_ms) << ','
              << quantile(t.frame_cpu_ms, 0.1) << ',' << quantile(t.frame_cpu_ms, 0.9) << ','
              << tolerance << ','
              << t.substeps_sum / std::max<std::size_t>(1, t.frame_ms.size()) << ','
              << t.estimate_sum << '\n';
        }
        if (t.samples.empty()) {
          csv << c.name << ',' << cfg.name() << ',' << cfg.substeps << ',' << cfg.iterations
              << ",,,,,,,,,," << median(t.frame_ms) << ",,," << t.rollbacks << ',' << status
              << ',' << median(t.frame_cpu_ms) << ",,\n";
        }
        csv.flush();
      }
      progress(static_cast<int>(configs.size()), static_cast<int>(configs.size()), c.name + " done");
    }
  }
}

}  // namespace cloth_sim::bench
