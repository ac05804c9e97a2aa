#include "cloth_sim/core/linalg/parallel.h"

#include <sched.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace cloth_sim {

int availableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

int resolveThreads(int requested) {
  static const int cores = availableCores();
  return requested > 0 ? requested : cores;
}

namespace {

/// How long a waiting thread spins before it sleeps: long enough to catch the next block loop
/// of the same iteration (they follow each other within microseconds), short enough that on a
/// machine busy with other work a waiting thread gives its core back almost at once (libgomp's
/// default spins for about 300,000 rounds first; sleeping at once, OMP_WAIT_POLICY=passive,
/// costs a system call per loop). No OpenMP build was measured against this team.
constexpr std::chrono::microseconds kSpin{50};

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

/// Spins on @p done for up to kSpin; true if it became true.
template <typename Done>
bool spinUntil(Done&& done) {
  const auto start = std::chrono::steady_clock::now();
  for (int round = 0;; ++round) {
    if (done()) return true;
    relax();
    if ((round & 63) == 63 && std::chrono::steady_clock::now() - start > kSpin) return false;
  }
}

/// The process's worker threads: persistent, started when first needed. A loop's blocks are
/// claimed one at a time from a shared counter by the calling thread and by every worker that
/// is awake, so a worker that the machine's other jobs keep off its core delays nothing: the
/// threads that run take its blocks (the caller waits only for blocks already started). Which
/// thread runs a block changes nothing in the result (each block writes only its own data).
class Team {
 public:
  /// Runs @p body on blocks [0, blocks) with up to @p threads threads (2 .. 65535); false,
  /// running nothing, if another thread is using the team (the caller then runs the loop
  /// itself).
  bool run(int threads, int blocks, void (*body)(void*, int), void* context) {
    std::unique_lock<std::mutex> owner(owner_, std::try_to_lock);
    if (!owner.owns_lock()) return false;
    grow(threads - 1);
    const std::uint64_t generation = ((state_.load(std::memory_order_relaxed) >> 16) + 1) & kGenerationMask;
    // Close the claims first: a late worker of the previous loop then claims nothing while the
    // job's fields change (it would otherwise read the new job under the old generation).
    claim_.store(generation << 32 | kClosed, std::memory_order_seq_cst);
    body_.store(body, std::memory_order_relaxed);
    context_.store(context, std::memory_order_relaxed);
    blocks_.store(blocks, std::memory_order_relaxed);
    finished_.store(0, std::memory_order_relaxed);
    claim_.store(generation << 32, std::memory_order_seq_cst);  // open: block 0 is next
    // The loop's generation and thread count in one word, what a sleeping worker waits on.
    state_.store(generation << 16 | static_cast<std::uint64_t>(threads), std::memory_order_seq_cst);
    if (sleepers_.load(std::memory_order_seq_cst) > 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      work_.notify_all();
    }
    help(generation);
    const auto all_done = [&] { return finished_.load(std::memory_order_seq_cst) == blocks; };
    if (!spinUntil(all_done)) {
      std::unique_lock<std::mutex> lock(mutex_);
      caller_waits_.store(true, std::memory_order_seq_cst);
      done_.wait(lock, all_done);
      caller_waits_.store(false, std::memory_order_relaxed);
    }
    return true;
  }

 private:
  static constexpr std::uint64_t kGenerationMask = 0xFFFFFFFFu;
  static constexpr std::uint64_t kClosed = 0xFFFFFFFFu;  ///< a claim index no loop reaches

  /// Claims and runs blocks of loop @p generation until none is left (or another loop began).
  void help(std::uint64_t generation) {
    while (true) {
      std::uint64_t claim = claim_.load(std::memory_order_acquire);
      if ((claim >> 32) != generation) return;
      const std::uint64_t block = claim & 0xFFFFFFFFu;
      const int blocks = blocks_.load(std::memory_order_relaxed);
      if (block >= static_cast<std::uint64_t>(blocks)) return;  // all claimed (or closed)
      void (*body)(void*, int) = body_.load(std::memory_order_relaxed);
      void* context = context_.load(std::memory_order_relaxed);
      // Succeeds only if no other thread claimed it and the loop is still this one, so the
      // fields read above are this loop's.
      if (!claim_.compare_exchange_weak(claim, claim + 1, std::memory_order_acq_rel)) continue;
      body(context, static_cast<int>(block));
      if (finished_.fetch_add(1, std::memory_order_seq_cst) + 1 == blocks &&
          caller_waits_.load(std::memory_order_seq_cst)) {
        std::lock_guard<std::mutex> lock(mutex_);
        done_.notify_one();
      }
    }
  }

  /// Starts workers up to @p workers; called before the next loop is published, so a new
  /// worker starts from the state before it and sees that loop as new.
  void grow(int workers) {
    while (static_cast<int>(threads_.size()) < workers) {
      const int index = static_cast<int>(threads_.size()) + 1;
      // The state now, not when the thread gets to run: by then the loop it was started for
      // may be published already, and a worker that took it as seen would sleep through it.
      const std::uint64_t before = state_.load(std::memory_order_acquire);
      threads_.emplace_back([this, index, before] { work(index, before); });
      threads_.back().detach();  // the team lives as long as the process
    }
  }

  void work(int index, std::uint64_t seen) {
    while (true) {
      const auto fresh = [&] { return state_.load(std::memory_order_acquire) != seen; };
      if (!spinUntil(fresh)) {
        sleepers_.fetch_add(1, std::memory_order_seq_cst);
        std::unique_lock<std::mutex> lock(mutex_);
        work_.wait(lock, fresh);
        sleepers_.fetch_sub(1, std::memory_order_relaxed);
      }
      seen = state_.load(std::memory_order_acquire);
      if (index >= static_cast<int>(seen & 0xFFFF)) continue;  // not in this loop
      help(seen >> 16);
    }
  }

  std::mutex owner_;  ///< held by the thread running a loop
  /// The loop's job (atomics: a late worker may read them while the next loop writes them; it
  /// then fails to claim and reads nothing it uses).
  std::atomic<void (*)(void*, int)> body_{nullptr};
  std::atomic<void*> context_{nullptr};
  std::atomic<int> blocks_{0};
  std::atomic<std::uint64_t> claim_{0};  ///< generation << 32 | the next block to claim
  std::atomic<int> finished_{0};         ///< blocks of the loop run to the end
  std::atomic<std::uint64_t> state_{0};  ///< generation << 16 | the loop's thread count
  std::atomic<int> sleepers_{0};
  std::atomic<bool> caller_waits_{false};
  std::mutex mutex_;
  std::condition_variable work_, done_;
  std::vector<std::thread> threads_;
};

Team& team() {
  static Team* const instance = new Team();  // never destroyed: its threads outlive main
  return *instance;
}

/// Whether this thread is inside a block loop's body (a nested loop then runs serially).
thread_local bool in_body = false;

}  // namespace

namespace detail {

void parallelForImpl(int threads, int blocks, void (*body)(void*, int), void* context) {
  threads = std::min({threads, blocks, 0xFFFF});
  if (!in_body && threads > 1) {
    struct Guarded {
      void (*body)(void*, int);
      void* context;
    } guarded{body, context};
    const auto run = [](void* g, int b) {
      const Guarded& inner = *static_cast<Guarded*>(g);
      in_body = true;
      inner.body(inner.context, b);
      in_body = false;
    };
    if (team().run(threads, blocks, run, &guarded)) return;
  }
  for (int b = 0; b < blocks; ++b) body(context, b);
}

}  // namespace detail
}  // namespace cloth_sim
