/// @file settings_table.h
/// Every tunable number of cloth_sim, once: its name, allowed range, unit and meaning, and the
/// one message that refuses a value outside it (Setting::refusal). The scene reader, the core's
/// validate functions and setters, the builders, the node's parameters and services, the
/// runner's options and cfg/ClothSim.cfg (compared by a test) all take their rule and their
/// message from here. The scene fields are described in docs/scene_format.md. A solver's own
/// settings (its block, solver.<name>.<field>) are Settings too, held by its registry entry
/// (solvers/registry.h) so that adding a solver stays within solvers/.
///
/// Adding a setting: one line below (and in kAllSettings), then use it where it is read.
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/settings/range.h"

namespace cloth_sim {

/// One tunable number.
struct Setting {
  const char* name;   ///< identifier, as the scene field where there is one ("solver.iterations")
  const char* param;  ///< the node's parameter / dynamic_reconfigure name, "" if not exposed
  Range range;        ///< allowed values
  bool integer;       ///< an int field (the range ends are then integers too)
  const char* unit;   ///< SI unit, "" when dimensionless
  const char* note;   ///< what a special value means, e.g. "(0 = hard pin)", or ""
  const char* doc;    ///< one line for users (cfg, --help)
  /// dynamic_reconfigure slider end when the range's own end is too far for a slider (0: the
  /// range's end, or not on a slider).
  double slider_max;

  /// Whether @p value is allowed: finite, inside the range and, for an integer setting, whole.
  bool allows(double value) const;
  /// The whole rule with its unit and note, for help texts and refusals: "in (0, 1e+06] m",
  /// "finite and > 0 s" (an unbounded range says what a bounded one implies), "an integer in
  /// [1, 50]", "an integer >= 1", "in [0, 1) (0 = the upper bound)".
  std::string requirement() const;
  /// The one message refusing a value: "" when @p value is allowed, else
  /// "<what> <value> must be <requirement>", e.g. "radius 0 must be in (0, 1e+06] m",
  /// "parameter '~max_rollbacks': 0 must be >= 1", "value 2.5 must be an integer in [2, 2000]"
  /// (an integer setting says "an integer" when the value is not whole; a whole value is refused
  /// by the range). @p what names the value as the caller's context calls it: a field, a
  /// service's request field, "parameter '~x':", or "value" after a scene field's path or a
  /// runner option. The value is shown with as many digits as it takes not to look allowed.
  std::string refusal(double value, const std::string& what) const;
  /// Throws std::invalid_argument(refusal(value, what)) unless @p value is allowed.
  void require(double value, const std::string& what) const;
  /// require(value, name).
  void require(double value) const { require(value, name); }
};

/// One tunable name: a choice among a fixed list of names (the list lives with its enum).
struct NameSetting {
  const char* name;   ///< scene field ("solver.integrator")
  const char* param;  ///< the node's parameter name, "" if not exposed
  const char* doc;    ///< one line for users (cfg, --help)
};

namespace settings {
/// SolverSettings::integrator; names from integratorNames() (solvers/solver.h).
inline constexpr NameSetting kIntegrator{"solver.integrator", "integrator",
                                         "Time discretisation: implicit_euler (default), bdf2 (less numerical damping) or implicit_midpoint (none)"};
// clang-format off
//                                  name                         param                   range                              int    unit      note                 doc                                                   slider
inline constexpr Setting kIterations{"solver.iterations",       "iterations",           Range::closed(1, 100000),           true,  "",       "",                  "Solver iterations per step (a cap for newton)",     0};
inline constexpr Setting kSubsteps{"solver.substeps",           "substeps",             Range::closed(0, 1000),             true,  "",       "(0 = chosen by the error estimate)", "Implicit steps per frame (each time_step / substeps); 0: chosen to meet error_tolerance", 0};
inline constexpr Setting kErrorTolerance{"solver.error_tolerance", "error_tolerance",   Range::closed(0, 1),                false, "m",      "(0 = fixed iterations)", "Position error a frame may make (RMS): iterations and substeps follow it", 0.01};
inline constexpr Setting kThreads{"solver.threads",           "threads",              Range::closed(0, 1024),             true,  "",       "(0 = every core)",  "Threads of a frame's kernels; results are the same for any count", 0};
// Below 1: the relative change of an iteration is |x_k - x_{k-1}| / |x_k - x_0|, which is 1 at
// the first iteration, so a tolerance of 1 or more stopped every step after one iteration.
inline constexpr Setting kTolerance{"solver.tolerance",         "",                     Range{0, 1, false, true},           false, "",       "(0 = never)",       "Stop below this relative position change (0 = never)", 0};
inline constexpr Setting kTimeStep{"time_step",                 "",                     Range::closed(1e-6, 1),             false, "s",      "",                  "Time step h",                                        0};
inline constexpr Setting kDivergenceStrain{"divergence_strain", "",                     Range::atLeast(1),                  false, "",       "(1 = 100 %)",       "Strain beyond which a step counts as diverged",      0};
inline constexpr Setting kArealDensity{"material.areal_density", "",                    Range::closed(1e-6, 1e6),           false, "kg/m^2", "",                  "Mass per area of the cloth",                         0};
inline constexpr Setting kDamping{"material.damping",           "damping",              Range::closed(0, 1e6),              false, "1/s",    "",                  "Linear drag rate gamma (1/s): velocity decays as exp(-gamma t)", 100};
inline constexpr Setting kStructuralStiffness{"material.springs.structural", "structural_stiffness", Range::closed(0, 1e9), false, "N/m",    "",                  "Stiffness of every structural spring (N/m)",         100000};
inline constexpr Setting kShearStiffness{"material.springs.shear", "shear_stiffness",   Range::closed(0, 1e9),              false, "N/m",    "",                  "Stiffness of every shear spring (N/m)",              100000};
inline constexpr Setting kBendingStiffness{"material.springs.bending", "bending_stiffness", Range::closed(0, 1e9),           false, "N/m",    "",                  "Stiffness of every bending spring (N/m)",            100000};
inline constexpr Setting kParticleMass{"particle.mass",         "",                     Range::above(0),                    false, "kg",     "",                  "Lumped mass of a particle (from the areal density)", 0};
inline constexpr Setting kRestLength{"spring.rest_length",      "",                     Range::above(0),                    false, "m",      "",                  "Rest length of a spring (from the cloth's geometry)", 0};
inline constexpr Setting kGridResolution{"cloth.grid.rows",     "",                     Range::closed(2, 2000),             true,  "",       "",                  "Particles along each side of a grid cloth",          0};
inline constexpr Setting kGridSize{"cloth.grid.size",           "",                     Range::closed(1e-3, 1e4),           false, "m",      "",                  "Width and height of a grid cloth",                   0};
inline constexpr Setting kMeshScale{"scale",                    "",                     Range::closed(1e-6, 1e6),           false, "",       "",                  "Uniform scale of an OBJ file",                       0};
inline constexpr Setting kBodySize{"collider.size",              "",                     Range{0, 1e6, true, false},         false, "m",      "",                  "A body collider's radius or box side",               0};
inline constexpr Setting kCapsuleLength{"collider.length",        "",                     Range::closed(0, 1e6),              false, "m",      "(0 = a sphere)",    "Distance between a capsule's cap centres",           0};
inline constexpr Setting kBodyMargin{"collider.margin",          "",                     Range{0, 1, true, false},           false, "m",      "",                  "Distance the cloth keeps from a body collider",      0};
inline constexpr Setting kMeshThickness{"thickness",            "",                     Range{0, 1, true, false},           false, "m",      "",                  "Contact distance of a mesh obstacle",                0};
inline constexpr Setting kPinStiffness{"pin.stiffness",         "stiffness",            Range::closed(0, 1e9),              false, "N/m",    "(0 = hard pin)",    "Stiffness of a soft pin",                            0};
inline constexpr Setting kSphereRadius{"sphere.radius",         "radius",               Range{0, 1e6, true, false},         false, "m",      "",                  "Radius of a sphere collider",                        0};
inline constexpr Setting kSphereMass{"sphere.mass",             "mass",                 Range::closed(0, 1e9),              false, "kg",     "(0 = kinematic)",   "Mass of a sphere (0: moves at its velocity)",       0};
inline constexpr Setting kRestitution{"sphere.restitution",     "restitution",          Range::closed(0, 1),                false, "",       "",                  "Share of the normal speed a sphere keeps on impact", 0};
inline constexpr Setting kFriction{"friction",                  "friction",             Range::closed(0, 100),              false, "",       "",                  "Coulomb friction coefficient mu",                    0};
inline constexpr Setting kSelfThickness{"self_collision.thickness", "",                Range::atLeast(0),                  false, "m",      "(0 = automatic: 2 mm, or the mean rest edge in mode particles)", "Distance the cloth keeps from itself",   0};
inline constexpr Setting kSelfFriction{"self_collision.friction", "",                  Range::atLeast(0),                  false, "",       "",                  "Coulomb friction of the cloth on itself",            0};
inline constexpr Setting kGraspRadius{"grasp.radius",          "",                     Range::atLeast(0),                  false, "m",      "(0 = the nearest free particle)", "Particles within this of a grasp point are held", 0};
inline constexpr Setting kRealTimeFactor{"real_time_factor",    "real_time_factor",     Range::closed(0, 1000),             false, "",       "(0 = as fast as possible)", "Simulated seconds per wall-clock second",     0};
inline constexpr Setting kGraspFrameTimeout{"grasp_frame_timeout", "grasp_frame_timeout", Range::above(0),                  false, "s",      "",                  "A grasp frame whose latest transform is older is stale", 0};
inline constexpr Setting kFrameBudget{"budget_ms",              "budget_ms",            Range::closed(0, 1000),             false, "ms",     "(0 = off)",         "Wall-clock budget of a frame: the substeps adapt to fit it (0 = off)", 100};
inline constexpr Setting kFrameDeadline{"frame_deadline_ms",   "frame_deadline_ms",    Range::closed(0, 60000),            false, "ms",     "(0 = none)",        "Wall-clock time a frame may take before its work is cut (iterations stopped, the rest of its substeps run as one)", 0};
inline constexpr Setting kTfBufferDuration{"tf_buffer_duration", "tf_buffer_duration", Range::closed(1, 3600),     false, "s",      "",                  "History kept by the node's tf buffer (a trajectory published ahead must fit in it)", 0};
inline constexpr Setting kForceArrowScale{"force_arrow_scale",  "force_arrow_scale",    Range::atLeast(0),                  false, "m/N",    "",                  "Length of a grasp's force arrow per newton",        0};
// The node's own parameters (src/node/options.cpp): drawing, pacing and recovery.
inline constexpr Setting kRenderRate{"render_rate",             "render_rate",          Range{0, 1000, true, false},        false, "Hz",     "",                  "Rate of cloth/markers (independent of the step rate)", 0};
inline constexpr Setting kMarkerBandwidth{"marker_bandwidth",   "marker_bandwidth",     Range::above(0),                    false, "bytes/s", "",                 "cloth/markers is sent less often than render_rate to stay under this", 0};
inline constexpr Setting kMaxRollbacks{"max_rollbacks",         "max_rollbacks",        Range::atLeast(1),                  true,  "",       "",                  "Rolled-back steps in a row after which the cloth is reset", 0};
inline constexpr Setting kStrainColorScale{"strain_color_scale", "strain_color_scale",  Range::above(0),                    false, "",       "(0.05 = 5 %)",      "Strain drawn at full colour",                        0};
inline constexpr Setting kSphereCullDistance{"sphere_cull_distance", "sphere_cull_distance", Range::above(0),               false, "m",      "",                  "A sphere farther than this from the cloth's initial centre is removed", 0};
inline constexpr Setting kMaxInteractivePins{"max_interactive_pins", "max_interactive_pins", Range::atLeast(0),             true,  "",       "(0 = none)",        "Pins get RViz drag handles while there are at most this many", 0};
inline constexpr Setting kSummaryPeriod{"summary_period",       "summary_period",       Range::atLeast(0),                  false, "s",      "(0 = off)",         "Period of the one-line summary in the log",          0};
// The headless runner's own options (tools/runner/run_scene.cpp).
inline constexpr Setting kRunDuration{"duration",               "",                     Range::above(0),                    false, "s",      "",                  "Simulated time of a run",                            0};
inline constexpr Setting kRunFrames{"frames",                   "",                     Range::closed(1, 100000000),        true,  "",       "(duration / frame, rounded)", "Frames of a run (about 19 days at 60 Hz at most)", 0};
inline constexpr Setting kFoldTime{"fold",                      "",                     Range::above(0),                    false, "s",      "",                  "Time to carry the first pin over the cloth",         0};
// Where things may be, and how hard gravity may pull: a coordinate within 1000 km of the origin
// keeps a double's resolution under 1e-9 m there, so rest lengths and contacts stay exact.
inline constexpr Setting kCoordinate{"position",                "",                     Range::closed(-1e6, 1e6),           false, "m",      "",                  "Any coordinate of a scene (positions, centres, targets, corners, ground height)", 0};
inline constexpr Setting kSimTime{"sim_time",                   "",                     Range::closed(0, 1e9),              false, "s",      "",                  "Simulated time of a state",                          0};
inline constexpr Setting kGravity{"gravity",                    "",                     Range::closed(-1e3, 1e3),           false, "m/s^2",  "(per axis)",        "Gravity, each component",                            0};

/// Every setting above, in that order (a solver's own settings are in its registry entry).
inline constexpr const Setting* kAllSettings[] = {
    &kIterations, &kSubsteps, &kErrorTolerance, &kThreads, &kTolerance, &kTimeStep,
    &kDivergenceStrain, &kArealDensity, &kDamping,
    &kStructuralStiffness, &kShearStiffness, &kBendingStiffness, &kParticleMass,
    &kRestLength, &kGridResolution, &kGridSize, &kMeshScale,
    &kBodySize, &kCapsuleLength, &kBodyMargin,
    &kMeshThickness, &kPinStiffness, &kSphereRadius, &kSphereMass,
    &kRestitution, &kFriction, &kSelfThickness, &kSelfFriction,
    &kGraspRadius, &kRealTimeFactor, &kGraspFrameTimeout, &kFrameBudget, &kFrameDeadline,
    &kTfBufferDuration, &kForceArrowScale, &kRenderRate, &kMarkerBandwidth, &kMaxRollbacks,
    &kStrainColorScale, &kSphereCullDistance, &kMaxInteractivePins, &kSummaryPeriod,
    &kRunDuration, &kRunFrames, &kFoldTime, &kCoordinate,
    &kSimTime, &kGravity};
// clang-format on
}  // namespace settings

}  // namespace cloth_sim
