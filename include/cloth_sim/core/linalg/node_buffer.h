/// @file node_buffer.h
/// The padded node layout the local/global iterations stream over: x, y, z, 0 per node.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#include "cloth_sim/core/linalg/supernodal_solves.h"

namespace cloth_sim {

/// std::allocator with 64-byte (cache line) alignment, so a padded node never straddles two lines.
template <typename T>
struct CacheAlignedAllocator {
  using value_type = T;
  CacheAlignedAllocator() = default;
  template <typename U>
  CacheAlignedAllocator(const CacheAlignedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = ((n * sizeof(T) + 63) / 64) * 64;
    void* p = std::aligned_alloc(64, bytes == 0 ? 64 : bytes);
    if (p == nullptr) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <typename U>
  bool operator==(const CacheAlignedAllocator<U>&) const { return true; }
  template <typename U>
  bool operator!=(const CacheAlignedAllocator<U>&) const { return false; }
};

/// Node positions or right-hand sides: kNodeStride doubles per node (x, y, z, 0), in a solver's
/// node order, cache-line aligned.
using NodeBuffer = std::vector<double, CacheAlignedAllocator<double>>;

}  // namespace cloth_sim
