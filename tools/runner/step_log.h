// Per-step output of the headless runner: CSV or JSON, one record per step.
#pragma once

#include <fstream>
#include <ostream>
#include <string>

#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim::tools {

/// One step as the runner reports it.
struct StepRecord {
  int step = 0;             ///< 1-based
  double time = 0.0;        ///< s of simulated time after the step
  StepReport report;        ///< solver iterations, convergence, wall time, strain, status
  double energy = 0.0;      ///< J, Simulation::totalEnergy after the step
};

/// Writes StepRecords as CSV (header + one line per step) or JSON (an object with the run's
/// description and a "steps" array). Non-finite numbers become empty (CSV) or null (JSON).
class StepLog {
 public:
  enum class Format { kCsv, kJson };
  /// Opens @p path ("-" = stdout). Throws std::runtime_error if it cannot be written.
  StepLog(const std::string& path, Format format);
  ~StepLog();
  /// JSON only: the run's metadata, written before the steps ({"key": "value", ...} pairs).
  void begin(const std::string& scene, const std::string& solver, int particles, int springs,
             double time_step, int iterations);
  void write(const StepRecord& record);
  /// Closes the JSON document.
  void end();

 private:
  std::ofstream file_;
  std::ostream* out_;
  Format format_;
  bool first_ = true;
  bool ended_ = false;
};

/// Writes final positions as CSV: header "particle,x,y,z", one row per particle (m).
void writePositions(const std::string& path, const Points& positions);

/// A one-line progress bar on stderr, redrawn at most 10 times a second; silent unless stderr
/// is a terminal.
class ProgressBar {
 public:
  explicit ProgressBar(int total_steps);
  void update(int done, double sim_time, double mean_step_ms);
  void finish();

 private:
  int total_;
  bool enabled_;
  double last_draw_ = -1.0;
  double start_;
};

}  // namespace cloth_sim::tools
