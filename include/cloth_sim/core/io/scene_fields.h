/// @file scene_fields.h
/// Typed reading of a scene's YAML nodes (yaml-cpp), each failure a SceneError naming the field
/// by its dotted path; numbers are checked against their Setting (settings_table.h) and refused
/// with its message. The field readers of scene_reader.cpp are written on it.
#pragma once

#include <cstddef>
#include <set>
#include <string>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "cloth_sim/core/io/scene_error.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

/// Reads the fields of one scene source (a file path or the name given to parseScene).
class SceneFields {
 public:
  /// Values longer than this are cut in messages: a 100 kB value is not echoed back whole.
  static constexpr std::size_t kShown = 64;

  /// Fields of the scene @p source (named in every SceneError; relative files resolve against
  /// its directory).
  explicit SceneFields(std::string source) : source_(std::move(source)) {}

  /// Throws SceneError(source, @p path, @p problem).
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const;

  /// @p node as flow YAML, cut to kShown characters.
  static std::string show(const YAML::Node& node);
  /// @p text, or its first kShown characters and how long it was.
  static std::string clip(const std::string& text);
  /// "@p path.@p key", or @p key at the top level (empty @p path).
  static std::string join(const std::string& path, const std::string& key);

  /// Checks that @p node is a map whose keys are plain names, each given once and in @p known
  /// (an unknown one is refused listing the known ones).
  void map(const YAML::Node& node, const std::string& path,
           const std::set<std::string>& known) const;
  /// A finite number; also accepts a fraction written "a/b" (e.g. time_step: 1/60).
  double number(const YAML::Node& node, const std::string& path) const;
  /// A number @p setting allows, else fails with its refusal: "value <v> must be <rule>".
  double number(const YAML::Node& node, const std::string& path, const Setting& setting) const;
  /// An integer @p setting (an integer setting) allows, else fails with its refusal.
  int integer(const YAML::Node& node, const std::string& path, const Setting& setting) const;
  /// Any integer (an index the builder checks), else fails with "value V must be an integer".
  int integer(const YAML::Node& node, const std::string& path) const;
  /// [x, y, z], each component finite and, when @p setting is given, allowed by it.
  Vec3 vec3(const YAML::Node& node, const std::string& path,
            const Setting* setting = nullptr) const;
  /// A point of the scene: every coordinate allowed by settings::kCoordinate (m).
  Vec3 point(const YAML::Node& node, const std::string& path) const;
  /// A string.
  std::string text(const YAML::Node& node, const std::string& path) const;
  /// A name from a fixed list (solver, integrator, pattern, edge): short, so that the message
  /// listing the names can quote it.
  std::string word(const YAML::Node& node, const std::string& path) const;
  /// true or false.
  bool boolean(const YAML::Node& node, const std::string& path) const;

  /// The scene's file path or name, as given.
  const std::string& source() const { return source_; }
  /// @p file as given if absolute, else relative to the directory of the scene file.
  std::string resolve(const std::string& file) const;

 private:
  std::string source_;
};

}  // namespace cloth_sim
