/// @file strain_field.h
/// Per-particle strain: a scalar field over the particles for display (the ROS node colours
/// the cloth with it). Read-only; no physics depends on it.
#pragma once

#include <Eigen/Core>

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Signed strain of each particle (dimensionless): over the springs that touch the particle,
/// the strain (l - r) / r of largest magnitude, so > 0 means stretched and < 0 compressed.
///
/// Only the in-plane families (structural and shear) count when the model has any: bending
/// springs shorten whenever the cloth folds, which is curvature, not strain. A model with
/// neither uses every spring. A particle with no counted spring gets 0, and so does a spring
/// whose strain is not finite (the field is for display and must stay drawable).
/// Throws std::invalid_argument if @p positions does not have one column per particle.
Eigen::VectorXd vertexStrain(const Model& model, const Points& positions);

}  // namespace cloth_sim
