/// @file scene_error.h
/// The error of a scene that cannot be used, naming the field at fault.
#pragma once

#include <stdexcept>
#include <string>

namespace cloth_sim {

/// A scene file that cannot be used. what() reads
/// "<source>: field '<path>': <problem>" (or "<source>: <problem>", e.g. a YAML syntax error
/// with its line); a refused number's problem is Setting::refusal's "value <v> must be <rule>".
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& source, const std::string& field, const std::string& problem);
  /// Dotted path of the offending field, e.g. "cloth.grid.rows" or "pins[2].row".
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

}  // namespace cloth_sim
