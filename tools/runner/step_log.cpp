#include "step_log.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <stdexcept>

namespace cloth_sim::tools {
namespace {

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string number(double v, bool json) {
  if (!std::isfinite(v)) return json ? "null" : "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

StepLog::StepLog(const std::string& path, Format format) : out_(&std::cout), format_(format) {
  if (path != "-") {
    file_.open(path);
    if (!file_) throw std::runtime_error("cannot write '" + path + "'");
    out_ = &file_;
  }
  if (format_ == Format::kCsv) {
    *out_ << "step,time,wall_ms,solve_ms,iterations,convergence,converged,max_strain,energy,"
             "contacts,status,self_contacts,intersections,self_contact_ms,intersection_ms,substeps,"
             "total_iterations,iteration_error,error_estimate,rejected_substeps,"
             "carried_iteration_error,cut_substeps,merged_substeps\n";
  }
}

StepLog::~StepLog() { end(); }

void StepLog::begin(const std::string& scene, const std::string& solver, int particles,
                    int springs, double time_step, int iterations) {
  if (format_ != Format::kJson) return;
  *out_ << "{\"scene\": " << quoted(scene) << ", \"solver\": " << quoted(solver)
        << ", \"particles\": " << particles << ", \"springs\": " << springs
        << ", \"time_step\": " << number(time_step, true) << ", \"iterations\": " << iterations
        << ",\n \"steps\": [";
}

void StepLog::write(const StepRecord& r) {
  const bool json = format_ == Format::kJson;
  const StepReport& s = r.report;
  if (json) {
    *out_ << (first_ ? "\n  " : ",\n  ") << "{\"step\": " << r.step
          << ", \"time\": " << number(r.time, true)
          << ", \"wall_ms\": " << number(1e3 * s.wall_time, true)
          << ", \"solve_ms\": " << number(1e3 * s.solve_time, true)
          << ", \"iterations\": " << s.iterations
          << ", \"convergence\": " << number(s.convergence, true)
          << ", \"converged\": " << (s.converged ? "true" : "false")
          << ", \"max_strain\": " << number(s.max_strain, true)
          << ", \"energy\": " << number(r.energy, true) << ", \"contacts\": " << s.contacts
          << ", \"status\": " << quoted(stepStatusName(s.status))
          << ", \"self_contacts\": " << s.self_contacts
          << ", \"intersections\": " << s.intersections
          << ", \"self_contact_ms\": " << number(1e3 * s.self_contact_time, true)
          << ", \"intersection_ms\": " << number(1e3 * s.intersection_time, true)
          << ", \"substeps\": " << s.substeps << ", \"total_iterations\": " << s.total_iterations
          << ", \"iteration_error\": " << number(s.iteration_error, true)
          << ", \"error_estimate\": " << number(s.error_estimate, true)
          << ", \"rejected_substeps\": " << s.rejected_substeps
          << ", \"carried_iteration_error\": " << number(s.carried_iteration_error, true)
          << ", \"cut_substeps\": " << s.cut_substeps
          << ", \"merged_substeps\": " << s.merged_substeps << "}";
  } else {
    *out_ << r.step << ',' << number(r.time, false) << ',' << number(1e3 * s.wall_time, false)
          << ',' << number(1e3 * s.solve_time, false) << ',' << s.iterations << ','
          << number(s.convergence, false) << ',' << (s.converged ? 1 : 0) << ','
          << number(s.max_strain, false) << ',' << number(r.energy, false) << ',' << s.contacts
          << ',' << stepStatusName(s.status) << ',' << s.self_contacts << ',' << s.intersections
          << ',' << number(1e3 * s.self_contact_time, false) << ','
          << number(1e3 * s.intersection_time, false) << ',' << s.substeps << ','
          << s.total_iterations << ',' << number(s.iteration_error, false) << ','
          << number(s.error_estimate, false) << ',' << s.rejected_substeps << ','
          << number(s.carried_iteration_error, false) << ',' << s.cut_substeps << ','
          << s.merged_substeps << '\n';
  }
  first_ = false;
}

void StepLog::end() {
  if (ended_) return;
  ended_ = true;
  if (format_ == Format::kJson) *out_ << (first_ ? "]}\n" : "\n ]}\n");
  out_->flush();
}

void writePositions(const std::string& path, const Points& positions) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
  out << "particle,x,y,z\n" << std::setprecision(17);
  for (Eigen::Index i = 0; i < positions.cols(); ++i) {
    out << i << ',' << positions(0, i) << ',' << positions(1, i) << ',' << positions(2, i) << '\n';
  }
  if (!out) throw std::runtime_error("error while writing '" + path + "'");
}

ProgressBar::ProgressBar(int total_steps)
    : total_(total_steps), enabled_(isatty(STDERR_FILENO) != 0), start_(nowSeconds()) {}

void ProgressBar::update(int done, double sim_time, double mean_step_ms) {
  if (!enabled_) return;
  const double now = nowSeconds();
  // Only on long runs (past the first second) and at most 10 redraws a second.
  if (now - start_ < 1.0 || (last_draw_ >= 0.0 && now - last_draw_ < 0.1 && done < total_)) return;
  last_draw_ = now;
  constexpr int kWidth = 30;
  const double fraction = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
  const int filled = static_cast<int>(fraction * kWidth);
  const double eta = fraction > 0.0 ? (now - start_) * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r[%s%s] %3.0f%%  t = %.2f s  %.3f ms/step  ETA %.0f s ",
               std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(),
               100.0 * fraction, sim_time, mean_step_ms, eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (enabled_ && last_draw_ >= 0.0) std::fprintf(stderr, "\n");
  last_draw_ = -1.0;
}

}  // namespace cloth_sim::tools
