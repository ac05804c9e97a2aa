#include "cloth_sim/core/settings/settings_table.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace cloth_sim {
namespace {

bool whole(double value) { return std::isfinite(value) && value == std::floor(value); }

/// The rule with its unit and note; "an integer " first when @p say_integer.
std::string ruleText(const Setting& s, bool say_integer) {
  std::string text = say_integer ? "an integer " : "";
  if (!s.range.bounded() && !s.integer) text += "finite and ";  // "in [a, b]" says it already
  text += s.range.rule();
  if (*s.unit != '\0') text += std::string(" ") + s.unit;
  if (*s.note != '\0') text += std::string(" ") + s.note;
  return text;
}

}  // namespace

bool Setting::allows(double value) const {
  return range.contains(value) && (!integer || whole(value));
}

std::string Setting::requirement() const { return ruleText(*this, integer); }

std::string Setting::refusal(double value, const std::string& what) const {
  if (allows(value)) return "";
  // Six digits unless they read as an allowed number (1e-06 for 9.99e-07 next to [1e-06, 1]).
  std::string shown = formatNumber(value);
  for (int digits = 7; digits <= 17 && allows(std::strtod(shown.c_str(), nullptr)); ++digits) {
    shown = formatNumber(value, digits);
  }
  // An integer setting says so when the value is not one; a whole value is refused by the range.
  return what + " " + shown + " must be " + ruleText(*this, integer && !whole(value));
}

void Setting::require(double value, const std::string& what) const {
  if (!allows(value)) throw std::invalid_argument(refusal(value, what));
}

}  // namespace cloth_sim
