// Small statistics helpers for the benchmark.
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace cloth_sim::bench {

/// The p-quantile (0..1) of @p values by linear interpolation; NaN when empty.
inline double quantile(std::vector<double> values, double p) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double pos = p * (values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - lo) * (values[hi] - values[lo]);
}

inline double median(const std::vector<double>& values) { return quantile(values, 0.5); }

inline double maxOf(const std::vector<double>& values) {
  double m = -std::numeric_limits<double>::infinity();
  for (double v : values) m = std::max(m, v);
  return values.empty() ? std::numeric_limits<double>::quiet_NaN() : m;
}

/// CPU seconds this thread has run: unlike the wall clock, it does not count the time the
/// machine's other jobs hold the core (the benchmark shares 2 cores with other work).
inline double threadCpuNow() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Wall-clock seconds since an arbitrary epoch.
inline double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Wall-clock milliseconds of one call of @p f.
inline double timeMs(const std::function<void()>& f) {
  const double t0 = now();
  f();
  return 1e3 * (now() - t0);
}

/// @p dir/@p file opened for writing (the folder made if missing) with @p header as its first
/// line; @p path gets the file's path. Throws std::runtime_error if it cannot be written.
inline std::ofstream openCsv(const std::string& dir, const std::string& file,
                             const std::string& header, std::string& path) {
  std::filesystem::create_directories(dir);
  path = dir + "/" + file;
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  csv << header << '\n';
  return csv;
}

}  // namespace cloth_sim::bench
