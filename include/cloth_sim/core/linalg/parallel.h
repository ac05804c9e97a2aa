/// @file parallel.h
/// The kernels' threads: a fixed split of the work into blocks, and a loop that runs the blocks
/// on up to N threads (a persistent team of std::threads that claim blocks from a shared
/// counter, and spin briefly, then sleep, between loops). The
/// split depends on the problem only, never on the thread count, and every sum over blocks is
/// added in block order, so a kernel gives the same bits on any number of threads
/// (docs/architecture.md, "Threads").
#pragma once

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace cloth_sim {

/// Cores this process may run on (its CPU affinity mask; at least 1).
int availableCores();

/// The threads a `threads` setting asks for (settings::kThreads): @p requested, or every core
/// (availableCores) for 0.
int resolveThreads(int requested);

/// [0, count) cut into blocks of @p grain items (the last one shorter): block b is
/// [b * grain, min((b + 1) * grain, count)). A function of count and grain only.
struct BlockSplit {
  std::size_t count = 0;  ///< items split
  std::size_t grain = 1;  ///< items per block (>= 1)

  BlockSplit() = default;
  /// @p count items in blocks of @p grain (0 is taken as 1).
  BlockSplit(std::size_t count, std::size_t grain) : count(count), grain(std::max<std::size_t>(grain, 1)) {}
  /// Number of blocks, ceil(count / grain).
  int blocks() const { return static_cast<int>((count + grain - 1) / grain); }
  /// First item of block @p b.
  std::size_t begin(int b) const { return static_cast<std::size_t>(b) * grain; }
  /// One past the last item of block @p b.
  std::size_t end(int b) const { return std::min(count, begin(b) + grain); }
};

/// Fewest blocks a loop must have to run on more than one thread (parallelFor's default).
/// The kernels' blocks take about 10-50 us each; below 4 of them, waking and waiting for a
/// second thread costs more than it saves on a machine whose cores are busy with other work.
constexpr int kMinParallelBlocks = 4;

namespace detail {
void parallelForImpl(int threads, int blocks, void (*body)(void*, int), void* context);
}  // namespace detail

/// Calls @p body(b) once for every block b in [0, @p blocks), on up to @p threads threads (the
/// blocks claimed one at a time by whichever thread is free, so a thread that the machine keeps
/// waiting delays no one). Which thread runs a block is unspecified: body(b) must write only
/// what block b owns, and must not throw. Serial, in block order, when @p threads <= 1 or there
/// are fewer than @p min_blocks blocks (a loop of a few small blocks costs more to share than
/// it saves; the solves, whose few blocks are large, pass 2); a call from inside a body, or
/// while another thread's loop holds the team, also runs serially.
template <typename Body>
void parallelFor(int threads, int blocks, Body&& body, int min_blocks = kMinParallelBlocks) {
  if (threads <= 1 || blocks <= 1 || blocks < min_blocks) {
    for (int b = 0; b < blocks; ++b) body(b);
    return;
  }
  using B = std::remove_reference_t<Body>;
  detail::parallelForImpl(
      threads, blocks, [](void* context, int b) { (*static_cast<B*>(context))(b); },
      const_cast<void*>(static_cast<const void*>(&body)));
}

/// sum_b @p block_sum(b) over [0, @p blocks): the blocks in parallel (parallelFor), their sums
/// added in block order: the same bits for any thread count.
template <typename BlockSum>
double orderedSum(int threads, int blocks, BlockSum&& block_sum) {
  std::vector<double> partial(static_cast<std::size_t>(std::max(blocks, 0)), 0.0);
  parallelFor(threads, blocks, [&](int b) { partial[b] = block_sum(b); });
  double sum = 0.0;
  for (double p : partial) sum += p;
  return sum;
}

}  // namespace cloth_sim
