#include "cloth_sim/core/collision/self_contact.h"

#include <algorithm>
#include <ctime>
#include <limits>
#include <stdexcept>

#include "cloth_sim/core/collision/surface_topology.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

const char* selfContactModeName(SelfContactMode mode) {
  return mode == SelfContactMode::kParticles ? "particles" : "triangles";
}

SelfContactMode selfContactModeFromName(const std::string& name) {
  if (name == "triangles") return SelfContactMode::kTriangles;
  if (name == "particles") return SelfContactMode::kParticles;
  throw std::invalid_argument("self_collision.mode '" + name +
                              "' must be one of triangles, particles");
}

void SelfContactSettings::validate() const {
  settings::kSelfThickness.require(thickness);
  settings::kSelfFriction.require(friction);
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

SelfContact::SelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest,
                         const SelfContactSettings& settings)
    : mode_(settings.mode), friction_(settings.friction) {
  settings.validate();
  const SurfaceTopology topology(triangles, static_cast<int>(rest.cols()));  // checks indices
  const double mean_edge = topology.meanEdgeLength(rest);
  thickness_ = settings.thickness > 0.0                    ? settings.thickness
               : mode_ == SelfContactMode::kParticles ? mean_edge
                                                        : std::min(kAutomaticThickness, mean_edge);
  if (!(thickness_ > 0.0)) {
    throw std::invalid_argument(
        "self_collision.thickness: 0 (automatic) needs a cloth with "
        "triangles of non-zero size; give a thickness > 0 m");
  }
  if (mode_ == SelfContactMode::kParticles) {
    const double least = ParticleSelfContact::minimumThickness(triangles, rest);
    // The table's refusal for a floor that depends on the cloth.
    const Setting rule{settings::kSelfThickness.name, "", Range::atLeast(least), false, "m",
                       "in mode particles for this cloth: 1.05 x the widest gap between the "
                       "particles of a rest triangle (docs/method.md, \"The particle mode\"); "
                       "give mode: triangles for a thinner cloth",
                       "", 0};
    rule.require(thickness_);
    particles_ = std::make_unique<ParticleSelfContact>(triangles, rest, thickness_, friction_);
  } else {
    const Setting rule{settings::kSelfThickness.name, "", Range::atLeast(kMinimumThickness), false,
                       "m",
                       "in mode triangles: thinner, contacts pressed by the ground and stopped "
                       "impacts come within rounding of touching (docs/method.md, \"Self-contact\")",
                       "", 0};
    rule.require(thickness_);
    triangles_ = std::make_unique<TriangleSelfContact>(triangles, rest, thickness_, friction_);
  }
}

SelfContact::~SelfContact() = default;
SelfContact::SelfContact(const SelfContact& other)
    : mode_(other.mode_),
      thickness_(other.thickness_),
      friction_(other.friction_),
      particles_(other.particles_ ? std::make_unique<ParticleSelfContact>(*other.particles_)
                                  : nullptr),
      triangles_(other.triangles_ ? std::make_unique<TriangleSelfContact>(*other.triangles_)
                                  : nullptr),
      cpu_seconds_(other.cpu_seconds_) {}
SelfContact::SelfContact(SelfContact&&) noexcept = default;
SelfContact& SelfContact::operator=(SelfContact&&) noexcept = default;

void SelfContact::setThreads(int threads) {
  if (particles_) particles_->setThreads(threads);
  if (triangles_) triangles_->setThreads(threads);
}

double SelfContact::maxDisplacement() const {
  return particles_ ? particles_->maxDisplacement() : std::numeric_limits<double>::infinity();
}

int SelfContact::limitDisplacement(const CollisionStep& step, Points& end, Points& velocities) {
  if (!particles_) return 0;
  const double t0 = threadCpuSeconds();
  const int limited = particles_->limitDisplacement(step, end, velocities);
  cpu_seconds_ += threadCpuSeconds() - t0;
  return limited;
}

int SelfContact::resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
                         Points& velocities) {
  const double t0 = threadCpuSeconds();
  const int moved = particles_ ? particles_->resolve(step, ground, end, velocities)
                               : triangles_->resolve(step, ground, end, velocities);
  cpu_seconds_ += threadCpuSeconds() - t0;
  return moved;
}

std::vector<std::pair<int, int>> SelfContact::contacts(const Points& positions) {
  return particles_ ? particles_->contacts(positions) : std::vector<std::pair<int, int>>();
}

long SelfContact::rebuilds() const { return particles_ ? particles_->rebuilds() : 0; }

}  // namespace cloth_sim
