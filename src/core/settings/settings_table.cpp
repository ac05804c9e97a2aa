#include "cloth_sim/core/settings/settings_table.h"

#include <stdexcept>

namespace cloth_sim {

std::string Setting::requirement() const {
  std::string text = range.rule();
  if (*unit != '\0') text += std::string(" ") + unit;
  if (*note != '\0') text += std::string(" ") + note;
  return text;
}

void Setting::require(double value) const {
  if (!range.contains(value)) {
    throw std::invalid_argument(std::string(name) + " = " + formatNumber(value) + " must be " +
                                requirement());
  }
}

}  // namespace cloth_sim
