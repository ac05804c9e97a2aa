#include "cloth_sim/core/model/material.h"

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

void Material::validate() const {
  settings::kArealDensity.require(areal_density);
  if (has_structural) settings::kStructuralStiffness.require(structural);
  if (has_shear) settings::kShearStiffness.require(shear);
  if (has_bending) settings::kBendingStiffness.require(bending);
}

}  // namespace cloth_sim
