#include "cloth_sim/core/settings/range.h"

#include <cmath>
#include <sstream>

namespace cloth_sim {

bool Range::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above_min = min_open ? value > min : value >= min;
  const bool below_max = max_open ? value < max : value <= max;
  return above_min && below_max;
}

std::string Range::rule() const {
  if (!bounded()) return (min_open ? "> " : ">= ") + formatNumber(min);
  return std::string("in ") + (min_open ? "(" : "[") + formatNumber(min) + ", " +
         formatNumber(max) + (max_open ? ")" : "]");
}

std::string formatNumber(double value, int significant_digits) {
  std::ostringstream s;
  s.precision(significant_digits);
  s << value;
  return s.str();
}

}  // namespace cloth_sim
