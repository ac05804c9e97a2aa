#include "cloth_sim/node/conversions.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cloth_sim::node {
namespace {

std::string str(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

/// A message with x, y, z fields holding @p v.
template <class Msg>
Msg xyzMsg(const Vec3& v) {
  Msg m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

}  // namespace

Vec3 toVec3(const geometry_msgs::Point& p) { return Vec3(p.x, p.y, p.z); }
Vec3 toVec3(const geometry_msgs::Vector3& v) { return Vec3(v.x, v.y, v.z); }

geometry_msgs::Point toPointMsg(const Vec3& v) { return xyzMsg<geometry_msgs::Point>(v); }
geometry_msgs::Vector3 toVector3Msg(const Vec3& v) { return xyzMsg<geometry_msgs::Vector3>(v); }

void requireFinite(const Vec3& v, const std::string& what) {
  if (!v.allFinite()) {
    throw std::invalid_argument(what + " (" + str(v.x()) + ", " + str(v.y()) + ", " +
                                str(v.z()) + ") is not finite");
  }
}

SphereCollider sphereFromRequest(const SpawnSphere::Request& request, const Vec3& center,
                                 const Vec3& velocity) {
  SphereCollider sphere;
  sphere.center = center;
  sphere.radius = request.radius;
  sphere.velocity = velocity;
  sphere.friction = request.friction;
  sphere.mass = request.mass;
  sphere.restitution = request.restitution;
  // The core's rules for a sphere are Colliders::addSphere's; asked of an empty set they refuse
  // without touching any simulation, before SceneLimits (which assumes a valid sphere) is asked.
  Colliders().addSphere(sphere);
  return sphere;
}

PinInfo toPinInfo(const Pin& pin, const Vec3& vertex_position) {
  PinInfo info;
  info.id = pin.id;
  info.vertex = pin.vertex;
  info.target = toPointMsg(pin.target);
  info.position = toPointMsg(vertex_position);
  info.stiffness = pin.stiffness;
  info.grasp = -1;
  return info;
}

SphereInfo toSphereInfo(const SphereCollider& sphere) {
  SphereInfo info;
  info.id = sphere.id;
  info.center = toPointMsg(sphere.center);
  info.radius = sphere.radius;
  info.velocity = toVector3Msg(sphere.velocity);
  info.friction = sphere.friction;
  info.mass = sphere.mass;
  info.angular_velocity = toVector3Msg(sphere.angular_velocity);
  info.restitution = sphere.restitution;
  return info;
}

ClothState toClothState(const Simulation& sim, const StepReport& report,
                        const StepCounters& counters, const std_msgs::Header& header) {
  ClothState s;
  s.header = header;
  s.step = counters.step;
  s.sim_time = sim.state().time;
  s.time_step = sim.frameTime();
  s.step_wall_time = report.wall_time;
  s.solve_wall_time = report.solve_time;
  s.solver = sim.solver().name();
  s.iterations = report.iterations;
  s.total_iterations = report.total_iterations;
  s.iteration_error = report.iteration_error;
  s.error_estimate = report.error_estimate;
  s.carried_iteration_error = report.carried_iteration_error;
  s.error_tolerance = report.error_tolerance;
  s.tolerance_unreachable = report.tolerance_unreachable;
  s.rejected_substeps = report.rejected_substeps;
  s.substeps = report.substeps;
  s.cut_substeps = report.cut_substeps;
  s.merged_substeps = report.merged_substeps;
  s.convergence = report.convergence;
  s.converged = report.converged;
  s.max_strain = report.max_strain;
  s.energy = sim.totalEnergy();
  s.contacts = report.contacts;
  s.self_intersections = report.intersections;
  s.status = stepStatusName(report.status);
  s.message = report.message;
  s.consecutive_failures = counters.consecutive_failures;
  s.divergence_resets = counters.divergence_resets;
  const Points& x = sim.state().positions;
  const std::vector<Pin>& pins = sim.pins().pins();
  for (std::size_t p = 0; p < pins.size(); ++p) {
    s.pins.push_back(toPinInfo(pins[p], x.col(pins[p].vertex)));
    if (p < sim.pinLoads().size()) s.pins.back().force = toVector3Msg(sim.pinLoads()[p]);
  }
  for (const Grasp& g : sim.grasps()) {
    for (PinInfo& info : s.pins) {
      for (int id : g.pin_ids) {
        if (info.id == id) info.grasp = g.id;
      }
    }
  }
  for (const SphereCollider& sphere : sim.colliders().spheres()) {
    s.spheres.push_back(toSphereInfo(sphere));
  }
  return s;
}

std::uint32_t frameStateQueue(int particles, std::uint32_t frames_per_call) {
  const double bytes = 48.0 * std::max(particles, 0) + 256.0;  // the header, step and digest
  const double fits = std::floor(kFrameStateQueueBytes / bytes);
  return static_cast<std::uint32_t>(
      std::max(10.0, std::min(static_cast<double>(frames_per_call), fits)));
}

}  // namespace cloth_sim::node
