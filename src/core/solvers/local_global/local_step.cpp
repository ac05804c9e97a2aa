#include "cloth_sim/core/solvers/local_global/local_step.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
  node_begin.clear();  // the partition's ranges no longer hold
}

void SpringTable::partition(int nodes, int grain) {
  const BlockSplit split(static_cast<std::size_t>(std::max(nodes, 1)), static_cast<std::size_t>(grain));
  const int count = split.blocks();
  node_begin.assign(count + 1, nodes);
  for (int k = 0; k < count; ++k) node_begin[k] = static_cast<int>(split.begin(k));
  node_begin[0] = 0;
  const auto block_of = [&](int node) { return static_cast<int>(node / split.grain); };
  spring_begin.assign(count + 1, static_cast<int>(size()));
  out_begin.assign(count + 1, 0);
  std::vector<std::vector<std::array<int, 3>>> incoming(count);  // slot, node, sign
  int slots = 0;
  for (int s = static_cast<int>(size()) - 1; s >= 0; --s) {
    spring_begin[block_of(std::min(a[s], b[s]))] = s;
  }
  for (int k = count - 1; k > 0; --k) spring_begin[k - 1] = std::min(spring_begin[k - 1], spring_begin[k]);
  for (int k = 0; k < count; ++k) {
    out_begin[k] = slots;
    for (int s = spring_begin[k]; s < spring_begin[k + 1]; ++s) {
      const int upper = std::max(a[s], b[s]);
      if (upper < node_begin[k + 1]) continue;
      incoming[block_of(upper)].push_back({slots++, upper, upper == a[s] ? 1 : -1});
    }
  }
  out_begin[count] = slots;
  incoming_begin.assign(1, 0);
  incoming_slot.clear();
  incoming_node.clear();
  incoming_sign.clear();
  for (const auto& list : incoming) {
    for (const auto& [slot, node, sign] : list) {
      incoming_slot.push_back(slot);
      incoming_node.push_back(node);
      incoming_sign.push_back(sign);
    }
    incoming_begin.push_back(static_cast<int>(incoming_slot.size()));
  }
  boundary_push.assign(static_cast<std::size_t>(kNodeStride) * slots, 0.0);
}

namespace {

/// Where one block's pushes go: the right-hand side rows of its own nodes (below @c limit), and
/// for the upper end of a boundary spring the next slot of @c boundary, as (d, scale): the
/// block that owns that end adds scale d with the same arithmetic (incoming pass).
struct BlockOut {
  double* rhs;
  int limit;
  double* boundary;

  double* nextSlot() {
    double* slot = boundary;
    boundary += kNodeStride;
    return slot;
  }
};

/// r += sign * scale * d, fused (one rounding, as the AVX2 path) or not (portable).
template <bool kFused>
inline void addScaled(double* r, double scale, const double* d, int n) {
  for (int c = 0; c < n; ++c) r[c] = kFused ? std::fma(scale, d[c], r[c]) : r[c] + scale * d[c];
}

/// One spring of the local step: rhs_a += scale d, rhs_b -= scale d with scale = h^2 k r / |d|,
/// d = x_a - x_b (the reference formulation; also the AVX2 path's fallback and tail).
template <bool kFused>
inline double localStepOne(const SpringTable& sp, std::size_t s, const double* x, BlockOut& out) {
  const double* xa = x + kNodeStride * sp.a[s];
  const double* xb = x + kNodeStride * sp.b[s];
  double d[3] = {xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]};
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double stretch = len - sp.rest[s];
  double scale = 0.0;
  int n = 3;
  if (len > 1e-300 && len <= 1e300) {
    scale = sp.weight[s] / len;
  } else {  // collapsed (or non-finite) spring: any direction has the same energy; use +x
    scale = sp.weight[s];
    d[0] = 1.0;
    n = 1;
  }
  for (const auto& [node, sign] : {std::pair<int, double>{sp.a[s], scale}, {sp.b[s], -scale}}) {
    if (node < out.limit) {
      addScaled<kFused>(out.rhs + kNodeStride * node, sign, d, n);
    } else {
      // (d, scale) for a fused end; (scale d, 1) for the other, which a fused or a plain
      // multiply-add by 1 both add as it is.
      double* slot = out.nextSlot();
      const double by = kFused ? scale : 1.0, times = kFused ? 1.0 : scale;
      for (int c = 0; c < 3; ++c) slot[c] = c < n ? times * d[c] : 0.0;
      slot[3] = by;
    }
  }
  return sp.half_k[s] * stretch * stretch;
}

double localStepPortable(const SpringTable& springs, std::size_t begin, std::size_t end,
                         const double* x, BlockOut& out) {
  double energy = 0.0;
  for (std::size_t s = begin; s < end; ++s) energy += localStepOne<false>(springs, s, x, out);
  return energy;
}

#if defined(__x86_64__) && defined(__GNUC__)
/// Four springs at a time: their x_a - x_b (one 32-byte node each) are transposed to x, y, z
/// vectors so that the lengths, square roots and divisions run four wide; the pushes are added
/// back node by node in spring order (springs share nodes, so no scatter can be vectorised).
/// Measured on the paper cloth: 1.7x faster than the portable loop (docs/benchmark.md, "Performance").
__attribute__((target("avx2,fma"))) double localStepAvx2(const SpringTable& sp, std::size_t begin,
                                                        std::size_t end, const double* x,
                                                        BlockOut& out) {
  const std::size_t m4 = begin + (end - begin) - (end - begin) % 4;
  const int* a = sp.a.data();
  const int* b = sp.b.data();
  __m256d energy = _mm256_setzero_pd();
  double tail = 0.0;
  alignas(32) double scale[4];
  for (std::size_t s = begin; s < m4; s += 4) {
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
      for (int i = 0; i < 4; ++i) tail += localStepOne<true>(sp, s + i, x, out);
      continue;
    }
    const __m256d stretch = _mm256_sub_pd(len, _mm256_loadu_pd(sp.rest.data() + s));
    energy = _mm256_fmadd_pd(_mm256_mul_pd(_mm256_loadu_pd(sp.half_k.data() + s), stretch),
                             stretch, energy);
    _mm256_store_pd(scale, _mm256_div_pd(_mm256_loadu_pd(sp.weight.data() + s), len));
    for (int i = 0; i < 4; ++i) {
      // rhs_a += scale d, rhs_b -= scale d, each with one rounding. The lower end is always the
      // block's own; the upper one may be another block's: (d, scale) into a slot then.
      const __m256d sc = _mm256_set1_pd(scale[i]);
      const int ai = a[s + i], bi = b[s + i];
      if (ai < out.limit) {
        double* ra = out.rhs + kNodeStride * ai;
        _mm256_storeu_pd(ra, _mm256_fmadd_pd(sc, d[i], _mm256_loadu_pd(ra)));
      } else {
        _mm256_storeu_pd(out.nextSlot(), _mm256_blend_pd(d[i], sc, 0x8));
      }
      if (bi < out.limit) {
        double* rb = out.rhs + kNodeStride * bi;
        _mm256_storeu_pd(rb, _mm256_fnmadd_pd(sc, d[i], _mm256_loadu_pd(rb)));
      } else {
        _mm256_storeu_pd(out.nextSlot(), _mm256_blend_pd(d[i], sc, 0x8));
      }
    }
  }
  for (std::size_t s = m4; s < end; ++s) tail += localStepOne<true>(sp, s, x, out);
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, energy);
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail;
}

bool haveAvx2() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return yes;
}

/// Block @p k's incoming boundary pushes, r += sign scale d, each one 4-wide fused multiply-add
/// (the same roundings as std::fma per component, without its call per component).
__attribute__((target("avx2,fma"))) void addIncomingAvx2(const SpringTable& sp, int k,
                                                         const double* slots, double* rhs) {
  const __m256d zero = _mm256_setzero_pd();
  for (int e = sp.incoming_begin[k]; e < sp.incoming_begin[k + 1]; ++e) {
    const double* slot = slots + kNodeStride * sp.incoming_slot[e];
    double* r = rhs + kNodeStride * sp.incoming_node[e];
    const __m256d d = _mm256_blend_pd(_mm256_loadu_pd(slot), zero, 0x8);  // the pad lane adds 0
    const __m256d scale = _mm256_set1_pd(sp.incoming_sign[e] > 0 ? slot[3] : -slot[3]);
    _mm256_storeu_pd(r, _mm256_fmadd_pd(scale, d, _mm256_loadu_pd(r)));
  }
}
#endif

/// Whether localStepRange takes the AVX2 path, whose pushes are fused multiply-adds.
bool fusedPushes() {
#if defined(__x86_64__) && defined(__GNUC__)
  return haveAvx2();
#else
  return false;
#endif
}

/// The springs [begin, end) of one block into @p out.
double localStepRange(const SpringTable& springs, std::size_t begin, std::size_t end,
                      const double* x, BlockOut& out) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (haveAvx2()) return localStepAvx2(springs, begin, end, x, out);
#endif
  return localStepPortable(springs, begin, end, x, out);
}

}  // namespace

double localStep3(const SpringTable& sp, const double* x, double* rhs, int threads) {
  if (sp.node_begin.empty()) {  // one block: every node is its own
    BlockOut out{rhs, std::numeric_limits<int>::max(), nullptr};
    return localStepRange(sp, 0, sp.size(), x, out);
  }
  const int blocks = sp.blocks();
  double* slots = sp.boundary_push.data();
  const double energy = orderedSum(threads, blocks, [&](int k) {
    BlockOut out{rhs, sp.node_begin[k + 1], slots + kNodeStride * sp.out_begin[k]};
    return localStepRange(sp, sp.spring_begin[k], sp.spring_begin[k + 1], x, out);
  });
  // The boundary springs' pushes, each added by the block that owns its upper end, with the
  // arithmetic of the path that computed it.
  parallelFor(threads, blocks, [&](int k) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (fusedPushes()) return addIncomingAvx2(sp, k, slots, rhs);
#endif
    for (int e = sp.incoming_begin[k]; e < sp.incoming_begin[k + 1]; ++e) {
      const double* slot = slots + kNodeStride * sp.incoming_slot[e];
      double* r = rhs + kNodeStride * sp.incoming_node[e];
      const double scale = sp.incoming_sign[e] > 0 ? slot[3] : -slot[3];
      if (fusedPushes()) addScaled<true>(r, scale, slot, 3);
      else addScaled<false>(r, scale, slot, 3);
    }
  });
  return energy;
}

namespace {

double springEnergyRange(const SpringTable& springs, std::size_t begin, std::size_t end,
                         const double* x) {
  double energy = 0.0;
  for (std::size_t s = begin; s < end; ++s) {
    const double* xa = x + kNodeStride * springs.a[s];
    const double* xb = x + kNodeStride * springs.b[s];
    const double d0 = xa[0] - xb[0], d1 = xa[1] - xb[1], d2 = xa[2] - xb[2];
    const double stretch = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - springs.rest[s];
    energy += springs.half_k[s] * stretch * stretch;
  }
  return energy;
}

}  // namespace

double springEnergy3(const SpringTable& springs, const double* x, int threads) {
  if (springs.node_begin.empty()) return springEnergyRange(springs, 0, springs.size(), x);
  return orderedSum(threads, springs.blocks(), [&](int k) {
    return springEnergyRange(springs, springs.spring_begin[k], springs.spring_begin[k + 1], x);
  });
}

double inertiaAndGravity(const double* x, const double* y, const double* mass, int count,
                         const Vec3& gravity, double h2, int threads) {
  const BlockSplit split(static_cast<std::size_t>(std::max(count, 0)), kNodeGrain);
  return orderedSum(threads, split.blocks(), [&](int block) {
    double sum = 0.0;
    for (std::size_t k = split.begin(block); k < split.end(block); ++k) {
      const double* xk = x + kNodeStride * k;
      const double* yk = y + kNodeStride * k;
      const double e0 = xk[0] - yk[0], e1 = xk[1] - yk[1], e2 = xk[2] - yk[2];
      const double g_dot_x = gravity[0] * xk[0] + gravity[1] * xk[1] + gravity[2] * xk[2];
      sum += mass[k] * (0.5 * (e0 * e0 + e1 * e1 + e2 * e2) - h2 * g_dot_x);
    }
    return sum;
  });
}

void copyNodes(const NodeBuffer& from, NodeBuffer& to, int threads) {
  to.resize(from.size());
  const BlockSplit split(from.size() / kNodeStride, kNodeGrain);
  parallelFor(threads, split.blocks(), [&](int block) {
    std::copy(from.begin() + kNodeStride * split.begin(block),
              from.begin() + kNodeStride * split.end(block), to.begin() + kNodeStride * split.begin(block));
  });
}

}  // namespace cloth_sim
