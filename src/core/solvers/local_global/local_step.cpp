#include "cloth_sim/core/solvers/local_global/local_step.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

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

namespace {

/// One spring of the local step (the reference formulation; also the AVX2 path's fallback).
inline double localStepOne(const SpringTable& sp, std::size_t s, const double* x, double* rhs) {
  const double* xa = x + kNodeStride * sp.a[s];
  const double* xb = x + kNodeStride * sp.b[s];
  const double d0 = xa[0] - xb[0], d1 = xa[1] - xb[1], d2 = xa[2] - xb[2];
  const double len = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
  const double stretch = len - sp.rest[s];
  double* ra = rhs + kNodeStride * sp.a[s];
  double* rb = rhs + kNodeStride * sp.b[s];
  if (len > 1e-300 && len <= 1e300) {
    const double scale = sp.weight[s] / len;
    ra[0] += scale * d0;
    ra[1] += scale * d1;
    ra[2] += scale * d2;
    rb[0] -= scale * d0;
    rb[1] -= scale * d1;
    rb[2] -= scale * d2;
  } else {  // collapsed (or non-finite) spring: any direction has the same energy; use +x
    ra[0] += sp.weight[s];
    rb[0] -= sp.weight[s];
  }
  return sp.half_k[s] * stretch * stretch;
}

double localStepPortable(const SpringTable& springs, const double* x, double* rhs) {
  double energy = 0.0;
  for (std::size_t s = 0; s < springs.size(); ++s) energy += localStepOne(springs, s, x, rhs);
  return energy;
}

#if defined(__x86_64__) && defined(__GNUC__)
/// Four springs at a time: their x_a - x_b (one 32-byte node each) are transposed to x, y, z
/// vectors so that the lengths, square roots and divisions run four wide; the pushes are added
/// back node by node in spring order (springs share nodes, so no scatter can be vectorised).
/// Measured on the paper cloth: 1.7x faster than the portable loop (docs/benchmark.md, "Performance").
__attribute__((target("avx2,fma"))) double localStepAvx2(const SpringTable& sp, const double* x,
                                                        double* rhs) {
  const std::size_t m = sp.size(), m4 = m - m % 4;
  const int* a = sp.a.data();
  const int* b = sp.b.data();
  __m256d energy = _mm256_setzero_pd();
  double tail = 0.0;
  alignas(32) double scale[4];
  for (std::size_t s = 0; s < m4; s += 4) {
    __m256d d[4];
    for (int i = 0; i < 4; ++i) {
      d[i] = _mm256_sub_pd(_mm256_loadu_pd(x + kNodeStride * a[s + i]),
                           _mm256_loadu_pd(x + kNodeStride * b[s + i]));
    }
    const __m256d t0 = _mm256_unpacklo_pd(d[0], d[1]), t1 = _mm256_unpackhi_pd(d[0], d[1]);
    const __m256d t2 = _mm256_unpacklo_pd(d[2], d[3]), t3 = _mm256_unpackhi_pd(d[2], d[3]);
    const __m256d dx = _mm256_permute2f128_pd(t0, t2, 0x20);
    const __m256d dz = _mm256_permute2f128_pd(t0, t2, 0x31);
    const __m256d dy = _mm256_permute2f128_pd(t1, t3, 0x20);
    const __m256d len = _mm256_sqrt_pd(
        _mm256_fmadd_pd(dx, dx, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dz, dz))));
    const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(len, _mm256_set1_pd(1e-300), _CMP_GT_OQ),
                                     _mm256_cmp_pd(len, _mm256_set1_pd(1e300), _CMP_LE_OQ));
    if (_mm256_movemask_pd(ok) != 0xF) {  // a collapsed spring among the four: do them one by one
      for (int i = 0; i < 4; ++i) tail += localStepOne(sp, s + i, x, rhs);
      continue;
    }
    const __m256d stretch = _mm256_sub_pd(len, _mm256_loadu_pd(sp.rest.data() + s));
    energy = _mm256_fmadd_pd(_mm256_mul_pd(_mm256_loadu_pd(sp.half_k.data() + s), stretch),
                             stretch, energy);
    _mm256_store_pd(scale, _mm256_div_pd(_mm256_loadu_pd(sp.weight.data() + s), len));
    for (int i = 0; i < 4; ++i) {
      const __m256d push = _mm256_mul_pd(_mm256_set1_pd(scale[i]), d[i]);
      double* ra = rhs + kNodeStride * a[s + i];
      double* rb = rhs + kNodeStride * b[s + i];
      _mm256_storeu_pd(ra, _mm256_add_pd(_mm256_loadu_pd(ra), push));
      _mm256_storeu_pd(rb, _mm256_sub_pd(_mm256_loadu_pd(rb), push));
    }
  }
  for (std::size_t s = m4; s < m; ++s) tail += localStepOne(sp, s, x, rhs);
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, energy);
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail;
}

bool haveAvx2() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return yes;
}
#endif

}  // namespace

double localStep3(const SpringTable& springs, const double* x, double* rhs) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (haveAvx2()) return localStepAvx2(springs, x, rhs);
#endif
  return localStepPortable(springs, x, rhs);
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
