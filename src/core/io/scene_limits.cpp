#include "cloth_sim/core/io/scene_limits.h"

#include <sstream>
#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim {
namespace {

std::string str(const Vec3& v) {
  return "(" + formatNumber(v.x()) + ", " + formatNumber(v.y()) + ", " + formatNumber(v.z()) + ")";
}

}  // namespace

SceneLimits SceneLimits::of(const Simulation& sim, double reach) {
  // The initial state, not the current one: the bounds must not drift with the cloth.
  const Points& x = sim.initialPositions();
  SceneLimits limits;
  limits.center = x.rowwise().mean();  // what the node culls spheres around
  limits.size = (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).maxCoeff();
  limits.cloth_mass = sim.model().mass.sum();
  limits.reach = reach;
  return limits;
}

void SceneLimits::checkPoint(const std::string& what, const Vec3& point) const {
  if (!point.allFinite()) {
    throw std::invalid_argument(what + " " + str(point) + " m is not finite");
  }
  for (int k = 0; k < 3; ++k) {
    if (!settings::kCoordinate.allows(point[k])) {
      throw std::invalid_argument(
          what + " " + str(point) +
          " m: " + settings::kCoordinate.refusal(point[k], std::string(1, "xyz"[k])));
    }
  }
  const double distance = (point - center).norm();
  if (!(distance <= reach)) {
    throw std::invalid_argument(what + " " + str(point) + " m is " + formatNumber(distance) +
                                " m from the cloth's centre " + str(center) +
                                " m, beyond ~sphere_cull_distance = " + formatNumber(reach) +
                                " m (the reach of the scene: nothing may be put farther)");
  }
}

void SceneLimits::checkPinTarget(const std::string& what, const Vec3& point) const {
  checkPoint(what, point);
  const double distance = (point - center).norm(), pin_reach = kPinReachSizes * size;
  if (!(distance <= pin_reach)) {
    throw std::invalid_argument(what + " " + str(point) + " m is " + formatNumber(distance) +
                                " m from the cloth's centre " + str(center) + " m, beyond " +
                                formatNumber(kPinReachSizes) + " x the cloth's size = " +
                                formatNumber(pin_reach) +
                                " m (a pin farther away stretches the cloth past what it can "
                                "follow)");
  }
}

void SceneLimits::checkSphereAroundPins(const std::string& what, const SphereCollider& sphere,
                                        const std::vector<Pin>& pins, const Points& positions) {
  const std::string name = what.empty() ? "" : what + ": ";
  for (const Pin& pin : pins) {
    if (!pin.isHard() || pin.vertex < 0 || pin.vertex >= positions.cols()) continue;
    for (const Vec3& p : {Vec3(positions.col(pin.vertex)), pin.target}) {
      const double distance = (p - sphere.center).norm();
      if (distance < sphere.radius) {
        throw std::invalid_argument(
            name + "center " + str(sphere.center) + " m and radius " +
            formatNumber(sphere.radius) + " m: the sphere holds pin " + std::to_string(pin.id) +
            " (vertex " + std::to_string(pin.vertex) + ", " + formatNumber(distance) +
            " m from its centre) inside it: a pinned particle does not collide, so the cloth "
            "around it would stay stretched across the sphere's surface");
      }
    }
  }
}

void SceneLimits::checkSphere(const std::string& what, const SphereCollider& sphere,
                              double substep) const {
  const std::string name = what.empty() ? "" : what + ": ";
  checkPoint(name + "center", sphere.center);
  std::ostringstream s;
  if (!(sphere.radius <= size)) {
    s << name << "radius " << sphere.radius << " m must be at most the cloth's size, " << size
      << " m (a larger sphere around the cloth throws every particle to its surface)";
  } else if (sphere.mass > 0.0 && !(sphere.mass >= kMinBallToCloth * cloth_mass)) {
    s << name << "mass " << sphere.mass << " kg must be 0 (kinematic) or at least "
      << kMinBallToCloth << " times the cloth's mass, " << kMinBallToCloth * cloth_mass
      << " kg (a lighter ball is flung off by the particles it touches at unbounded speed)";
  } else if (!(sphere.mass <= kMaxBallToCloth * cloth_mass)) {
    s << name << "mass " << sphere.mass << " kg must be at most " << kMaxBallToCloth
      << " times the cloth's mass, " << kMaxBallToCloth * cloth_mass
      << " kg (a heavier ball tears through any cloth)";
  } else {
    const double speed = sphere.velocity.norm(), max_speed = sphere.radius / substep;
    if (!(speed <= max_speed)) {
      s << name << "velocity " << str(sphere.velocity) << " m/s: its speed " << speed << " m/s must be at most its radius per implicit step, "
        << sphere.radius << " m / " << substep << " s = " << max_speed
        << " m/s (faster, it crosses the cloth between two contact resolutions)";
    }
  }
  if (!s.str().empty()) throw std::invalid_argument(s.str());
}

}  // namespace cloth_sim
