// File: semgraph/core/stable_array.h
//
// StableArray<T>: a growable array whose elements never move. It backs the seqlocked edge
// values (edge_values.h), so that readers evaluating compiled queries on other threads may keep
// reading while the writer adds frames and edges (docs/realtime.md, "Topology changes while
// readers run"): a std::vector would reallocate and leave them reading freed memory.
//
// Layout: blocks of doubling size, block k holding kFirst << k elements (indices
// kFirst * (2^k - 1) up to kFirst * (2^(k+1) - 1) - 1), allocated once and freed only by the
// destructor. The block directory is a fixed array inside the object (kMaxBlocks entries cover
// every 32-bit index), so growing never moves it either.
//
// Invariants: elements [0, size()) are constructed; an element's address is fixed from its
// construction to the array's destruction (a move hands the blocks over unchanged); blocks
// [0, blocks) are allocated, capacity() = kFirst * (2^blocks - 1).
// Costs: operator[] O(1): a bit scan, two subtractions and the directory load (a compiled
// query keeps element pointers instead and pays none of it); Reserve allocates the missing
// blocks (at most doubling the capacity each); push/Resize construct in place, no allocation
// below capacity().
// Thread safety: one writer (Reserve, EmplaceBack, Resize). Readers on other threads may use
// elements (and pointers to them) that were constructed before the reader learned of them
// (happens-before, e.g. through the compiled query handed to the reader), concurrently with
// the writer appending others: growth writes only new directory entries and new elements.
// size() and capacity() are the writer's (not synchronized).
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::core {

template <class T, unsigned kFirstLog2 = 6>
class StableArray {
 public:
  static constexpr std::size_t kFirst = std::size_t{1} << kFirstLog2;
  /// Enough blocks for every 32-bit index.
  static constexpr std::size_t kMaxBlocks = 33 - kFirstLog2;

  StableArray() noexcept = default;
  StableArray(StableArray&& other) noexcept { Swap(other); }
  StableArray& operator=(StableArray&& other) noexcept {
    if (this != &other) {
      StableArray tmp(std::move(other));
      Swap(tmp);
    }
    return *this;
  }
  StableArray(const StableArray&) = delete;
  StableArray& operator=(const StableArray&) = delete;
  ~StableArray() {
    for (std::size_t i = 0; i < size_; ++i) (*this)[i].~T();
    for (std::size_t k = 0; k < blocks_; ++k)
      ::operator delete (block_[k], std::align_val_t{alignof(T)});
  }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] std::size_t capacity() const noexcept { return Start(blocks_); }

  [[nodiscard]] T& operator[](std::size_t i) noexcept { return At(i); }
  [[nodiscard]] const T& operator[](std::size_t i) const noexcept {
    return const_cast<StableArray*>(this)->At(i);
  }

  /// Allocates blocks until capacity() >= n (all or nothing: on std::bad_alloc the blocks
  /// allocated so far stay, unused, and nothing else changed).
  void Reserve(std::size_t n) {
    while (capacity() < n) {
      SEMGRAPH_DEMAND(blocks_ < kMaxBlocks);
      block_[blocks_] = static_cast<T*>(
          ::operator new (BlockSize(blocks_) * sizeof(T), std::align_val_t{alignof(T)}));
      ++blocks_;
    }
  }
  /// Constructs element size() in place (Reserve first, or this allocates).
  template <class... Args>
  T& EmplaceBack(Args&&... args) {
    Reserve(size_ + 1);
    T* p = ::new (static_cast<void*>(&At(size_))) T(std::forward<Args>(args)...);
    ++size_;
    return *p;
  }
  /// Grows to n elements, default-constructed (never shrinks: addresses stay valid).
  void Resize(std::size_t n) {
    Reserve(n);
    while (size_ < n) {
      ::new (static_cast<void*>(&At(size_))) T();
      ++size_;
    }
  }
  /// Bytes allocated for elements.
  [[nodiscard]] std::size_t bytes() const noexcept { return capacity() * sizeof(T); }

 private:
  static constexpr std::size_t BlockSize(std::size_t k) noexcept { return kFirst << k; }
  static constexpr std::size_t Start(std::size_t k) noexcept {
    return kFirst * ((std::size_t{1} << k) - 1);
  }
  T& At(std::size_t i) noexcept {
    const std::size_t j = i + kFirst;  // block k holds j in [kFirst << k, kFirst << (k + 1))
    const std::size_t k = static_cast<std::size_t>(std::bit_width(j)) - 1 - kFirstLog2;
    return block_[k][j - (kFirst << k)];
  }
  void Swap(StableArray& o) noexcept {
    std::swap(block_, o.block_);
    std::swap(blocks_, o.blocks_);
    std::swap(size_, o.size_);
  }

  std::array<T*, kMaxBlocks> block_{};
  std::size_t blocks_ = 0;
  std::size_t size_ = 0;
};

}  // namespace semgraph::core
