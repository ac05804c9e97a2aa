#include "cloth_sim/core/local_step.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace cloth_sim {

void SpringTable::add(int i, int j, double w, double k, double r) {
  a.push_back(i);
  b.push_back(j);
  weight.push_back(w);
  half_k.push_back(0.5 * k);
  rest.push_back(r);
}

void SpringTable::sortByNode() {
  std::vector<std::size_t> order(size());
  std::iota(order.begin(), order.end(), 0);
  auto key = [&](std::size_t s) {
    return std::make_pair(std::min(a[s], b[s]), std::max(a[s], b[s]));
  };
  std::sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return key(l) < key(r); });
  auto permute = [&](auto& v) {
    auto copy = v;
    for (std::size_t k = 0; k < order.size(); ++k) v[k] = copy[order[k]];
  };
  permute(a);
  permute(b);
  permute(weight);
  permute(half_k);
  permute(rest);
}

double localStep3(const SpringTable& springs, const double* x, double* rhs) {
  const int* a = springs.a.data();
  const int* b = springs.b.data();
  const double* weight = springs.weight.data();
  const double* half_k = springs.half_k.data();
  const double* rest = springs.rest.data();
  const std::size_t m = springs.size();
  double energy = 0.0;
  for (std::size_t s = 0; s < m; ++s) {
    const double* xa = x + kNodeStride * a[s];
    const double* xb = x + kNodeStride * b[s];
    const double d0 = xa[0] - xb[0], d1 = xa[1] - xb[1], d2 = xa[2] - xb[2];
    const double len = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const double stretch = len - rest[s];
    energy += half_k[s] * stretch * stretch;
    double* ra = rhs + kNodeStride * a[s];
    double* rb = rhs + kNodeStride * b[s];
    if (len > 1e-300 && len <= 1e300) {
      const double scale = weight[s] / len;
      ra[0] += scale * d0;
      ra[1] += scale * d1;
      ra[2] += scale * d2;
      rb[0] -= scale * d0;
      rb[1] -= scale * d1;
      rb[2] -= scale * d2;
    } else {  // collapsed (or non-finite) spring: any direction has the same energy; use +x
      ra[0] += weight[s];
      rb[0] -= weight[s];
    }
  }
  return energy;
}

double springEnergy3(const SpringTable& springs, const double* x) {
  double energy = 0.0;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const double* xa = x + kNodeStride * springs.a[s];
    const double* xb = x + kNodeStride * springs.b[s];
    const double d0 = xa[0] - xb[0], d1 = xa[1] - xb[1], d2 = xa[2] - xb[2];
    const double stretch = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - springs.rest[s];
    energy += springs.half_k[s] * stretch * stretch;
  }
  return energy;
}

double inertiaAndGravity(const double* x, const double* y, const double* mass, int count,
                         const Vec3& gravity, double h2) {
  double sum = 0.0;
  for (int k = 0; k < count; ++k) {
    const double* xk = x + kNodeStride * k;
    const double* yk = y + kNodeStride * k;
    const double e0 = xk[0] - yk[0], e1 = xk[1] - yk[1], e2 = xk[2] - yk[2];
    const double g_dot_x = gravity[0] * xk[0] + gravity[1] * xk[1] + gravity[2] * xk[2];
    sum += mass[k] * (0.5 * (e0 * e0 + e1 * e1 + e2 * e2) - h2 * g_dot_x);
  }
  return sum;
}

}  // namespace cloth_sim
