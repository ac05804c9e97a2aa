/// @file step_report.h
/// What a frame did and cost (StepReport), and whether its end state can be kept.
#pragma once

#include <string>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/model/model.h"

namespace cloth_sim {

/// Outcome of a step.
enum class StepStatus {
  kOk,         ///< step taken
  kNonFinite,  ///< the solver produced NaN/Inf: rolled back (see Simulation::step)
  kDiverged,   ///< max strain above SimulationOptions::divergence_strain: rolled back
};
/// "ok", "non_finite", "diverged".
const char* stepStatusName(StepStatus status);

/// What one step did and cost.
struct StepReport {
  StepStatus status = StepStatus::kOk;
  int substeps = 0;          ///< implicit steps taken in this frame (SolverSettings::substeps)
  int iterations = 0;        ///< solver iterations of the last substep (SolveResult)
  int total_iterations = 0;  ///< solver iterations of all the frame's substeps
  /// m: the largest estimated iteration error of the frame's substeps (SolveResult::
  /// iteration_error; 0 without error control).
  double iteration_error = 0.0;
  /// m: the frame's estimated local truncation error: its substeps' errors summed per particle,
  /// RMS over the particles (FrameError; 0 without error control).
  double error_estimate = 0.0;
  /// m: the frame's iteration errors carried to its end, sum over its substeps i = 1..n of
  /// (n - i + 1) e_i with e_i the substep's iteration_error. A position error e left by a
  /// substep's iterations is also a velocity error e / h, which moves the cloth by e again in
  /// each substep after it (the slow modes the iterations leave are those the implicit step does
  /// not damp), so the frame ends (n - i + 1) e_i off. The error controller does not use it
  /// (the substeps do not reduce it: the iteration stop does); error_estimate +
  /// carried_iteration_error is the frame's whole estimated error (docs/method.md, "Error
  /// control"). 0 where the substeps' iteration_error is.
  double carried_iteration_error = 0.0;
  /// m: the error a frame may make (SolverSettings::error_tolerance; 0: no error control).
  double error_tolerance = 0.0;
  /// The error tolerance needs more substeps than allowed (the maximum, or a frame budget):
  /// the next frames run at the allowed maximum and their error is over the tolerance.
  bool tolerance_unreachable = false;
  /// Substeps of the attempts at this frame that error control rejected and ran again with
  /// more substeps (Simulation::kRedoShare); substeps and the figures above are the kept run's.
  int rejected_substeps = 0;
  double convergence = 0.0;  ///< relative position change of the last iteration (last substep)
  bool converged = false;    ///< the solver tolerance was reached
  /// s of wall time in the solver (all substeps; its self-contact pairs also count in
  /// self_contact_time)
  double solve_time = 0.0;
  double wall_time = 0.0;    ///< s of wall time for the whole step (solve, contacts, checks)
  /// Contacts of the frame, summed over its substeps: contact forces that pushed in the solve
  /// plus particles moved out of a collider by the projection after it.
  int contacts = 0;
  /// Particles moved by self-contact (displacement bound and projection, summed over substeps).
  int self_contacts = 0;
  /// Pairs of triangles sharing no vertex that intersect after the step (IntersectionCounter):
  /// 0 for a cloth that did not pass through itself; -1 = not counted (self-collision off).
  int intersections = -1;
  /// s of wall time in self-contact (bound, projection, and its pairs' share of the solve)
  double self_contact_time = 0.0;
  double intersection_time = 0.0;  ///< s of wall time in the intersection counter
  double max_strain = 0.0;         ///< max |l - r| / r over the springs after the step
  /// Substeps of this frame whose implicit midpoint step gained energy and were redone as two
  /// implicit Euler steps of h/2 (MidpointSafeguard, docs/method.md "Implicit midpoint").
  int midpoint_fallbacks = 0;
  /// The frame deadline (Simulation::setFrameDeadline): substeps whose iterations it stopped
  /// before their count or tolerance, and substeps of the frame that were run as one at its
  /// end instead of their own (the frame still advances its whole time). Both 0 when the frame
  /// finished in time: the work the settings asked for was done.
  int cut_substeps = 0;
  int merged_substeps = 0;
  /// The frame did less work than its settings asked (cut or merged substeps).
  bool shortfall() const { return cut_substeps > 0 || merged_substeps > 0; }
  std::string message;  ///< empty when ok; otherwise what went wrong and what was done
};

/// Whether a frame that ended at @p state and @p colliders, with max spring strain
/// @p max_strain, can be kept: kNonFinite if a position, a velocity (cloth or sphere) or the
/// strain is not finite, kDiverged if the strain is above @p divergence_strain, else kOk.
StepStatus frameStatus(const State& state, const Colliders& colliders, double max_strain,
                       double divergence_strain);

/// The report's message for a frame of @p solver rolled back from @p status (not kOk), with
/// @p max_strain against @p divergence_strain, started at simulated time @p time (s).
std::string rollbackMessage(StepStatus status, const char* solver, double max_strain,
                            double divergence_strain, double time);

}  // namespace cloth_sim
