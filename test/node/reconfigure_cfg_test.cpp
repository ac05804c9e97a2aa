// cfg/ClothSim.cfg, as generated into ClothSimConfig, against its sources: the settings table
// (names, docs, ranges), the core structs (defaults) and the solver registry (the enum).
#include <regex>
#include <string>
#include <vector>

#include <boost/any.hpp>
#include <gtest/gtest.h>

#include <cloth_sim/ClothSimConfig.h>

#include "cloth_sim/core/io/scene_reader.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/registry.h"
#include "cloth_sim/node/options.h"

namespace cloth_sim {
namespace {

/// The value of the parameter @p d in @p config, as a double (int and double parameters).
double numberIn(const ClothSimConfig::AbstractParamDescriptionConstPtr& d,
                const ClothSimConfig& config) {
  boost::any value;
  d->getValue(config, value);
  return d->type == "int" ? boost::any_cast<int>(value) : boost::any_cast<double>(value);
}

const Setting* settingOfParam(const std::string& param) {
  for (const Setting* s : settings::kAllSettings) {
    if (param == s->param) return s;
  }
  return nullptr;
}

/// What the core starts from when a scene does not say (the cfg default of each parameter).
double coreDefault(const std::string& param) {
  static const SceneConfig scene;  // what parseScene starts from
  const Material& material = scene.grid.material;
  if (param == "structural_stiffness") return material.structural;
  if (param == "shear_stiffness") return material.shear;
  if (param == "bending_stiffness") return material.bending;
  if (param == "damping") return scene.damping;
  if (param == "iterations") return SolverSettings{}.max_iterations;
  if (param == "substeps") return SolverSettings{}.substeps;
  if (param == "error_tolerance") return SolverSettings{}.error_tolerance;
  if (param == "budget_ms") return node::NodeOptions{}.budget_ms;  // a node option: off
  ADD_FAILURE() << "no core default known for " << param;
  return 0.0;
}

TEST(ReconfigureCfg, NumericParametersMatchTheSettingsTable) {
  int numeric = 0;
  for (const auto& d : ClothSimConfig::__getParamDescriptions__()) {
    if (d->type != "int" && d->type != "double") continue;
    ++numeric;
    SCOPED_TRACE(d->name);
    const Setting* s = settingOfParam(d->name);
    ASSERT_NE(s, nullptr) << "not in settings_table.h";
    EXPECT_EQ(d->description, s->doc);
    EXPECT_EQ(d->type == "int", s->integer);
    EXPECT_EQ(numberIn(d, ClothSimConfig::__getMin__()), s->range.min);
    EXPECT_FALSE(s->range.min_open) << "a slider cannot leave out its end";
    // A slider ends where the table says (slider_max) when the allowed range is far wider.
    const double max = s->slider_max > 0.0 ? s->slider_max : s->range.max;
    EXPECT_EQ(numberIn(d, ClothSimConfig::__getMax__()), max);
    EXPECT_EQ(numberIn(d, ClothSimConfig::__getDefault__()), coreDefault(d->name));
  }
  EXPECT_EQ(numeric, 8);
}

TEST(ReconfigureCfg, SelfCollisionSwitchIsOffAsInAScene) {
  EXPECT_FALSE(ClothSimConfig::__getDefault__().self_collision);
  EXPECT_FALSE(SimulationOptions{}.self_contact.enabled);
}

TEST(ReconfigureCfg, SolverEnumIsTheRegistry) {
  const auto& descriptions = ClothSimConfig::__getParamDescriptions__();
  const auto solver = std::find_if(descriptions.begin(), descriptions.end(),
                                   [](const auto& d) { return d->name == "solver"; });
  ASSERT_NE(solver, descriptions.end());
  EXPECT_EQ(ClothSimConfig::__getDefault__().solver, SimulationOptions{}.solver);
  const std::string& edit = (*solver)->edit_method;
  const std::regex entry("'name': '(\\w+)', 'type': 'str', 'value': '\\w+', 'srcline': \\d+, "
                         "'srcfile': '[^']*', 'description': '([^']*)'");
  std::vector<std::string> names;
  std::size_t k = 0;
  for (auto it = std::sregex_iterator(edit.begin(), edit.end(), entry); it != std::sregex_iterator();
       ++it, ++k) {
    names.push_back((*it)[1]);
    ASSERT_LT(k, solverRegistry().size());
    EXPECT_EQ((*it)[2], solverRegistry()[k].description) << (*it)[1];
  }
  EXPECT_EQ(names, solverNames());
}

}  // namespace
}  // namespace cloth_sim
