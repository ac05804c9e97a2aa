#include "self_collision_set.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "cloth_sim/core/collision/triangle_self_contact.h"
#include "cloth_sim/core/io/scene.h"
#include "self_contact_cases.h"

namespace cloth_sim::bench {
namespace {

struct Row {
  cases::Case c;
  int particles = 0, max_intersections = 0, first_bad = -1, failed = 0;
  double closest = 0.0, max_strain = 0.0, wall_ms = 0.0, self_ms = 0.0, counter_ms = 0.0;
};

Row runCase(const cases::Case& c) {
  Row row;
  row.c = c;
  Simulation sim = makeSimulation(parseScene(c.yaml, c.name));
  if (sim.selfContact() == nullptr || sim.selfContact()->mode() != SelfContactMode::kTriangles) {
    throw std::logic_error("self_collision_set: the case is not in mode triangles");
  }
  const double t = sim.selfContact()->thickness();
  row.particles = sim.model().particleCount();
  std::vector<Vec3> start;
  for (int k = 1; k <= c.frames; ++k) {
    cases::beforeFrame(c, sim, k, start);
    const StepReport r = sim.step();
    // -1 (not counted) is flagged too: every frame must be checked.
    if (r.intersections != 0 && row.first_bad < 0) row.first_bad = k;
    row.max_intersections = std::max(row.max_intersections, std::abs(r.intersections));
    row.failed += r.status != StepStatus::kOk;
    row.max_strain = std::max(row.max_strain, r.max_strain);
    row.wall_ms += 1e3 * r.wall_time;
    row.self_ms += 1e3 * r.self_contact_time;
    row.counter_ms += 1e3 * r.intersection_time;
  }
  TriangleSelfContact probe(sim.model().triangles, sim.initialPositions(), t, 0.0);
  row.closest = probe.minPairDistance(sim.state().positions, t) / t;
  return row;
}

}  // namespace

int runSelfCollisionSet(const SelfCollisionSetOptions& o) {
  std::vector<Row> rows;
  int bad = 0;
  for (int k = 0; k < o.seeds; ++k) {
    const cases::Case c =
        cases::random(o.first_seed + k, o.min_resolution, o.max_resolution, o.seconds);
    const Row r = runCase(c);
    bad += r.max_intersections != 0 || r.failed != 0;
    std::printf("[self_collision_set] seed %u %s, t = %.0f mm, %d particles: max intersecting "
                "pairs %d, failed frames %d, closest %.2f t, %.0f ms per frame (self-contact "
                "%.0f %%)\n",
                c.seed, c.name.c_str(), 1e3 * c.thickness, r.particles, r.max_intersections,
                r.failed, r.closest, r.wall_ms / c.frames, 100.0 * r.self_ms / r.wall_ms);
    std::fflush(stdout);
    rows.push_back(r);
  }
  std::ofstream csv(o.out_dir + "/self_collision_set.csv");
  csv << "seed,kind,thickness_mm,resolution,particles,frames,max_intersections,first_bad_frame,"
         "failed_frames,closest_t,max_strain,wall_ms_per_frame,self_contact_share,counter_share\n";
  std::ofstream md(o.out_dir + "/self_collision_set.md");
  md << "| seed | kind | t (mm) | particles | frames | max intersecting pairs | failed frames | "
        "closest at the end (t) | max strain | ms per frame (wall) | self-contact / step |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    const cases::Case& c = r.c;
    csv << c.seed << ',' << c.name << ',' << 1e3 * c.thickness << ',' << c.resolution << ','
        << r.particles << ',' << c.frames << ',' << r.max_intersections << ',' << r.first_bad
        << ',' << r.failed << ',' << r.closest << ',' << r.max_strain << ','
        << r.wall_ms / c.frames << ',' << r.self_ms / r.wall_ms << ',' << r.counter_ms / r.wall_ms
        << '\n';
    char line[256];
    std::snprintf(line, sizeof line,
                  "| %u | %s | %.0f | %d | %d | %d | %d | %.2f | %.3f | %.0f | %.0f %% |\n", c.seed,
                  c.name.c_str(), 1e3 * c.thickness, r.particles, c.frames, r.max_intersections,
                  r.failed, r.closest, r.max_strain, r.wall_ms / c.frames,
                  100.0 * r.self_ms / r.wall_ms);
    md << line;
  }
  return bad;
}

}  // namespace cloth_sim::bench
