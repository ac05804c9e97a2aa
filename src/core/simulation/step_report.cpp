#include "cloth_sim/core/simulation/step_report.h"

#include <cmath>
#include <sstream>

namespace cloth_sim {

const char* stepStatusName(StepStatus status) {
  switch (status) {
    case StepStatus::kOk: return "ok";
    case StepStatus::kNonFinite: return "non_finite";
    case StepStatus::kDiverged: return "diverged";
  }
  return "unknown";
}

StepStatus frameStatus(const State& state, const Colliders& colliders, double max_strain,
                       double divergence_strain) {
  bool finite = state.allFinite() && std::isfinite(max_strain);
  for (const SphereCollider& s : colliders.spheres()) {
    finite =
        finite && s.center.allFinite() && s.velocity.allFinite() && s.angular_velocity.allFinite();
  }
  if (!finite) return StepStatus::kNonFinite;
  return max_strain > divergence_strain ? StepStatus::kDiverged : StepStatus::kOk;
}

std::string rollbackMessage(StepStatus status, const char* solver, double max_strain,
                            double divergence_strain, double time) {
  std::ostringstream msg;
  if (status == StepStatus::kDiverged) {
    msg << solver << " diverged: max strain " << max_strain << " > limit " << divergence_strain;
  } else {
    msg << solver << " produced a non-finite position or velocity";
  }
  msg << " at t = " << time << " s; rolled back to that state with zero velocities"
      << " (cloth and dynamic spheres)";
  return msg.str();
}

}  // namespace cloth_sim
