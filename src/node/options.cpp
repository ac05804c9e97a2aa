#include "cloth_sim/node/options.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/solver.h"
#include "cloth_sim/node/marker_builder.h"

namespace cloth_sim::node {
namespace {

[[noreturn]] void fail(const std::string& param, const std::string& problem) {
  throw std::invalid_argument("parameter '~" + param + "': " + problem);
}

/// ~iterations: the scene's range, plus 0 for "keep the scene's".
constexpr Setting kIterationsOverride{
    "iterations", "iterations", Range::closed(0, settings::kIterations.range.max), true, "",
    "(0 = the scene's)", "replaces the scene's iterations per step when > 0", 0};

/// ~substeps: the scene's range, plus 0 for "keep the scene's".
constexpr Setting kSubstepsOverride{
    "substeps", "substeps", Range::closed(0, settings::kSubsteps.range.max), true, "",
    "(0 = the scene's)", "replaces the scene's substeps per frame when > 0", 0};

/// ~robot_margin and ~robot_friction: a body collider's rules under the parameters' names.
constexpr Setting kRobotMargin{"robot_margin", "robot_margin", settings::kBodyMargin.range, false,
                               "m", "", "distance the cloth keeps from the robot's links", 0};
constexpr Setting kRobotFriction{"robot_friction", "robot_friction", settings::kFriction.range,
                                 false, "", "", "Coulomb friction of the robot's links", 0};

/// Whether ~scene is the bare name of a shipped scene: no '/' and no ".yaml".
bool isSceneName(const std::string& scene) {
  return scene.find('/') == std::string::npos &&
         (scene.size() < 5 || scene.compare(scene.size() - 5, 5, ".yaml") != 0);
}

const char* typeName(XmlRpc::XmlRpcValue::Type type) {
  switch (type) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return "a boolean";
    case XmlRpc::XmlRpcValue::TypeInt: return "an integer";
    case XmlRpc::XmlRpcValue::TypeDouble: return "a number";
    case XmlRpc::XmlRpcValue::TypeString: return "a string";
    case XmlRpc::XmlRpcValue::TypeArray: return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct: return "a map";
    default: return "an unsupported value";
  }
}

/// Typed access to the private namespace; each getter leaves @p out alone when the key is absent.
class ParamReader {
 public:
  explicit ParamReader(XmlRpc::XmlRpcValue params) : params_(std::move(params)) {}

  void get(const std::string& key, std::string& out) {
    if (XmlRpc::XmlRpcValue* v = find(key)) {
      expect(key, *v, XmlRpc::XmlRpcValue::TypeString, "a string");
      out = static_cast<std::string&>(*v);
    }
  }
  void get(const std::string& key, double& out) {
    if (XmlRpc::XmlRpcValue* v = find(key)) {
      if (v->getType() == XmlRpc::XmlRpcValue::TypeInt) {
        out = static_cast<int&>(*v);
        return;
      }
      expect(key, *v, XmlRpc::XmlRpcValue::TypeDouble, "a number");
      out = static_cast<double&>(*v);
    }
  }
  void get(const std::string& key, int& out) {
    if (XmlRpc::XmlRpcValue* v = find(key)) {
      expect(key, *v, XmlRpc::XmlRpcValue::TypeInt, "an integer");
      out = static_cast<int&>(*v);
    }
  }
  /// A list of strings, or one string of names separated by spaces or commas.
  void get(const std::string& key, std::vector<std::string>& out) {
    XmlRpc::XmlRpcValue* v = find(key);
    if (v == nullptr) return;
    out.clear();
    if (v->getType() == XmlRpc::XmlRpcValue::TypeString) {
      std::string word;
      for (char c : static_cast<std::string&>(*v) + " ") {
        if (c == ' ' || c == ',') {
          if (!word.empty()) out.push_back(word);
          word.clear();
        } else {
          word += c;
        }
      }
      return;
    }
    expect(key, *v, XmlRpc::XmlRpcValue::TypeArray, "a list of names");
    for (int k = 0; k < v->size(); ++k) {
      expect(key, (*v)[k], XmlRpc::XmlRpcValue::TypeString, "a list of names");
      out.push_back(static_cast<std::string&>((*v)[k]));
    }
  }
  void get(const std::string& key, bool& out) {
    if (XmlRpc::XmlRpcValue* v = find(key)) {
      expect(key, *v, XmlRpc::XmlRpcValue::TypeBoolean, "true or false");
      out = static_cast<bool&>(*v);
    }
  }

 private:
  XmlRpc::XmlRpcValue* find(const std::string& key) {
    if (params_.getType() != XmlRpc::XmlRpcValue::TypeStruct || !params_.hasMember(key)) {
      return nullptr;
    }
    return &params_[key];
  }
  static void expect(const std::string& key, const XmlRpc::XmlRpcValue& v,
                     XmlRpc::XmlRpcValue::Type type, const char* wanted) {
    if (v.getType() != type) {
      fail(key, std::string("expected ") + wanted + ", got " + typeName(v.getType()));
    }
  }

  XmlRpc::XmlRpcValue params_;
};

}  // namespace

NodeOptions parseNodeOptions(const XmlRpc::XmlRpcValue& private_params) {
  if (private_params.valid() &&
      private_params.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    throw std::invalid_argument("the private namespace '~' must hold named parameters");
  }
  ParamReader read(private_params);
  NodeOptions o;
  read.get("scene", o.scene);
  read.get("frame_id", o.frame_id);
  read.get("render_rate", o.render_rate);
  read.get("solver", o.solver);
  read.get("iterations", o.iterations);
  read.get("substeps", o.substeps);
  if (private_params.valid() && private_params.hasMember("threads")) {
    int threads = 0;
    read.get("threads", threads);
    o.threads = threads;
  }
  if (private_params.valid() && private_params.hasMember("error_tolerance")) {
    double tolerance = 0.0;
    read.get("error_tolerance", tolerance);
    o.error_tolerance = tolerance;
  }
  if (private_params.valid() && private_params.hasMember("self_collision")) {
    bool on = false;
    read.get("self_collision", on);
    o.self_collision = on;
  }
  read.get("max_rollbacks", o.max_rollbacks);
  read.get("strain_color_scale", o.strain_color_scale);
  read.get("shading", o.shading);
  read.get("color_mode", o.color_mode);
  read.get("sphere_cull_distance", o.sphere_cull_distance);
  read.get("max_interactive_pins", o.max_interactive_pins);
  read.get("summary_period", o.summary_period);
  read.get("publish_clock", o.publish_clock);
  read.get("real_time_factor", o.real_time_factor);
  read.get("start_paused", o.start_paused);
  read.get("budget_ms", o.budget_ms);
  read.get("frame_deadline_ms", o.frame_deadline_ms);
  read.get("grasp_frame_timeout", o.grasp_frame_timeout);
  read.get("force_arrow_scale", o.force_arrow_scale);
  read.get("marker_bandwidth", o.marker_bandwidth);
  read.get("tf_buffer_duration", o.tf_buffer_duration);
  read.get("robot_description", o.robot_description);
  read.get("robot_links", o.robot_links);
  read.get("robot_margin", o.robot_margin);
  read.get("robot_friction", o.robot_friction);
  validateNodeOptions(o);
  return o;
}

void validateNodeOptions(const NodeOptions& o) {
  if (o.scene.empty()) {
    fail("scene",
         "is required: a scene YAML file or the name of a shipped scene (a file of the "
         "package's config/scenes/ without its .yaml)");
  }
  if (o.frame_id.empty() || o.frame_id.front() == '/') {
    fail("frame_id", "'" + o.frame_id + "' must be a non-empty tf2 frame name without a "
                     "leading '/'");
  }
  if (!o.solver.empty()) {
    try {
      makeSolver(o.solver);
    } catch (const std::invalid_argument& e) {
      fail("solver", e.what());
    }
  }
  try {
    colorModeFromName(o.color_mode);
  } catch (const std::invalid_argument& e) {
    fail("color_mode", e.what());
  }
  if (o.threads) settings::kThreads.require(*o.threads, "parameter '~threads':");
  // Every number against its rule, in the order of NodeOptions.
  for (const auto& [value, setting] :
       {std::pair<double, const Setting*>{o.render_rate, &settings::kRenderRate},
        {static_cast<double>(o.iterations), &kIterationsOverride},
        {static_cast<double>(o.substeps), &kSubstepsOverride},
        {o.error_tolerance.value_or(0.0), &settings::kErrorTolerance},
        {static_cast<double>(o.max_rollbacks), &settings::kMaxRollbacks},
        {o.strain_color_scale, &settings::kStrainColorScale},
        {o.sphere_cull_distance, &settings::kSphereCullDistance},
        {static_cast<double>(o.max_interactive_pins), &settings::kMaxInteractivePins},
        {o.summary_period, &settings::kSummaryPeriod},
        {o.real_time_factor, &settings::kRealTimeFactor},
        {o.budget_ms, &settings::kFrameBudget},
        {o.frame_deadline_ms, &settings::kFrameDeadline},
        {o.grasp_frame_timeout, &settings::kGraspFrameTimeout},
        {o.force_arrow_scale, &settings::kForceArrowScale},
        {o.marker_bandwidth, &settings::kMarkerBandwidth},
        {o.tf_buffer_duration, &settings::kTfBufferDuration},
        {o.robot_margin, &kRobotMargin},
        {o.robot_friction, &kRobotFriction}}) {
    setting->require(value, "parameter '~" + std::string(setting->param) + "':");
  }
}

std::string resolveScenePath(const std::string& scene, const std::string& scene_dir) {
  return isSceneName(scene) ? scene_dir + "/" + scene + ".yaml" : scene;
}

std::vector<std::string> shippedScenes(const std::string& scene_dir) {
  std::vector<std::string> names;
  std::error_code error;  // a missing directory ships no scene
  for (const auto& entry : std::filesystem::directory_iterator(scene_dir, error)) {
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

SceneConfig loadScene(const NodeOptions& options, const std::string& scene_dir) {
  SceneConfig scene;
  try {
    scene = loadSceneFile(resolveScenePath(options.scene, scene_dir));
  } catch (const SceneError& e) {
    std::string problem = e.what();
    const std::vector<std::string> shipped = shippedScenes(scene_dir);
    if (isSceneName(options.scene) &&
        std::find(shipped.begin(), shipped.end(), options.scene) == shipped.end()) {
      std::string list;
      for (const std::string& name : shipped) list += (list.empty() ? "" : ", ") + name;
      problem += " (the shipped scenes: " + list + ")";
    }
    fail("scene", problem);
  }
  SceneOverrides overrides;
  if (!options.solver.empty()) overrides.solver = options.solver;
  if (options.iterations > 0) overrides.iterations = options.iterations;
  if (options.substeps > 0) overrides.substeps = options.substeps;
  overrides.error_tolerance = options.error_tolerance;
  overrides.self_collision = options.self_collision;
  overrides.threads = options.threads;
  return applyOverrides(std::move(scene), overrides);
}

Simulation buildScene(const SceneConfig& scene) {
  try {
    return makeSimulation(scene);
  } catch (const SceneError& e) {
    fail("scene", e.what());
  }
}

}  // namespace cloth_sim::node
