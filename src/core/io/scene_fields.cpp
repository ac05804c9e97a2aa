#include "cloth_sim/core/io/scene_fields.h"

#include <cmath>
#include <map>

namespace cloth_sim {

SceneError::SceneError(const std::string& source, const std::string& field,
                       const std::string& problem)
    : std::runtime_error(source + ": " + (field.empty() ? "" : "field '" + field + "': ") +
                         problem),
      field_(field) {}

void SceneFields::fail(const std::string& path, const std::string& problem) const {
  throw SceneError(source_, path, problem);
}

std::string SceneFields::show(const YAML::Node& node) {
  YAML::Emitter out;
  out << YAML::Flow << node;
  return clip(out.c_str());
}

std::string SceneFields::clip(const std::string& text) {
  if (text.size() <= kShown) return text;
  return text.substr(0, kShown) + "... (" + std::to_string(text.size()) + " characters)";
}

std::string SceneFields::join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

void SceneFields::map(const YAML::Node& node, const std::string& path,
                      const std::set<std::string>& known) const {
  if (!node.IsMap()) fail(path, "value " + show(node) + " must be a map");
  std::map<std::string, int> lines;  // key -> line, to refuse a key given twice
  for (const auto& kv : node) {
    const int line = kv.first.Mark().line + 1;
    if (!kv.first.IsScalar()) {
      fail(path.empty() ? "(top level)" : path,
           "key " + show(kv.first) + " on line " + std::to_string(line) + " must be a plain name");
    }
    const std::string key = kv.first.Scalar();
    if (const auto [first, fresh] = lines.emplace(key, line); !fresh) {
      fail(join(path, clip(key)), "given twice (lines " + std::to_string(first->second) + " and " +
                                      std::to_string(line) + "); a field may appear once");
    }
    if (known.count(key) == 0) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(join(path, clip(key)), "unknown field (known here: " + list + ")");
    }
  }
}

double SceneFields::number(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(path, "value " + show(node) + " must be a number");
  const std::string text = node.Scalar();
  double value = 0.0;
  const auto slash = text.find('/');
  try {
    if (slash != std::string::npos) {
      std::size_t used_a = 0, used_b = 0;
      const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
      const double num = std::stod(a, &used_a), den = std::stod(b, &used_b);
      if (used_a != a.size() || used_b != b.size()) throw std::invalid_argument("fraction");
      value = num / den;
    } else {
      value = node.as<double>();
    }
  } catch (const std::exception&) {
    fail(path, "value '" + clip(text) + "' must be a number");
  }
  if (!std::isfinite(value)) fail(path, "value '" + clip(text) + "' must be finite");
  return value;
}

double SceneFields::number(const YAML::Node& node, const std::string& path,
                           const Setting& setting) const {
  const double value = number(node, path);
  if (!setting.allows(value)) fail(path, setting.refusal(value, "value"));
  return value;
}

int SceneFields::integer(const YAML::Node& node, const std::string& path,
                         const Setting& setting) const {
  // Whole and within an int: an integer setting's range ends are ints.
  return static_cast<int>(number(node, path, setting));
}

int SceneFields::integer(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(path, "value " + show(node) + " must be an integer");
  try {
    return node.as<int>();
  } catch (const std::exception&) {
    fail(path, "value " + show(node) + " must be an integer");
  }
}

Vec3 SceneFields::vec3(const YAML::Node& node, const std::string& path,
                       const Setting* setting) const {
  if (!node.IsSequence() || node.size() != 3) {
    fail(path, "value " + show(node) + " must be a list of 3 numbers [x, y, z]");
  }
  Vec3 v;
  for (int k = 0; k < 3; ++k) {
    const std::string component = path + "[" + std::to_string(k) + "]";
    v[k] = setting ? number(node[k], component, *setting) : number(node[k], component);
  }
  return v;
}

Vec3 SceneFields::point(const YAML::Node& node, const std::string& path) const {
  return vec3(node, path, &settings::kCoordinate);
}

std::string SceneFields::text(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(path, "value " + show(node) + " must be a string");
  return node.Scalar();
}

std::string SceneFields::word(const YAML::Node& node, const std::string& path) const {
  const std::string name = text(node, path);
  if (name.size() > kShown) fail(path, "value '" + clip(name) + "' is too long for a name");
  return name;
}

bool SceneFields::boolean(const YAML::Node& node, const std::string& path) const {
  try {
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    fail(path, "value " + show(node) + " must be true or false");
  }
}

std::string SceneFields::resolve(const std::string& file) const {
  if (!file.empty() && file[0] == '/') return file;
  const auto slash = source_.find_last_of('/');
  return slash == std::string::npos ? file : source_.substr(0, slash + 1) + file;
}

}  // namespace cloth_sim
