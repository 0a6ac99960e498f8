// File: semgraph/base/stable_array.h
//
// StableArray<T>: a growable array whose elements never move. It backs the seqlocked edge
// values (core/edge_values.h), so that readers on other threads (compiled queries keep element
// addresses) may keep reading while the writer adds frames and edges (docs/realtime.md,
// "Topology changes while readers run"): a std::vector would reallocate and leave them
// reading freed memory.
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
// elements [0, size()) concurrently with the writer appending others: growth writes only new
// directory entries (published with release, loaded with acquire) and new elements, and size()
// is published after the element is constructed. capacity() is the writer's. An index at or
// beyond size() must not be used (a reader checks it against size(), or got it from a field
// the writer stored after constructing the element).
#pragma once

#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

#include "semgraph/base/demand.h"
#include "semgraph/base/published.h"

namespace semgraph::base {

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
    for (std::size_t i = 0; i < size(); ++i) (*this)[i].~T();
    for (std::size_t k = 0; k < blocks_; ++k)
      ::operator delete (Block(k), std::align_val_t{alignof(T)});
  }

  [[nodiscard]] std::size_t size() const noexcept { return size_.load(); }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  [[nodiscard]] std::size_t capacity() const noexcept { return Start(blocks_); }

  [[nodiscard]] T& operator[](std::size_t i) noexcept { return At(i); }
  [[nodiscard]] const T& operator[](std::size_t i) const noexcept {
    return const_cast<StableArray*>(this)->At(i);
  }
  [[nodiscard]] T& back() noexcept { return At(size() - 1); }
  [[nodiscard]] const T& back() const noexcept { return (*this)[size() - 1]; }

  /// Allocates blocks until capacity() >= n (all or nothing: on std::bad_alloc the blocks
  /// allocated so far stay, unused, and nothing else changed).
  void Reserve(std::size_t n) {
    while (capacity() < n) {
      SEMGRAPH_DEMAND(blocks_ < kMaxBlocks);
      const std::size_t elements = kFirst << blocks_;
      block_[blocks_].store(
          static_cast<T*>(::operator new (elements * sizeof(T), std::align_val_t{alignof(T)})),
          std::memory_order_release);
      ++blocks_;
    }
  }
  /// Constructs element size() in place (Reserve first, or this allocates).
  template <class... Args>
  T& EmplaceBack(Args&&... args) {
    const std::size_t n = size();
    Reserve(n + 1);
    T* p = ::new (static_cast<void*>(&At(n))) T(std::forward<Args>(args)...);
    size_.store(n + 1);
    return *p;
  }
  /// Grows to n elements, default-constructed (never shrinks: addresses stay valid).
  void Resize(std::size_t n) {
    Reserve(n);
    for (std::size_t i = size(); i < n; ++i) {
      ::new (static_cast<void*>(&At(i))) T();
      size_.store(i + 1);
    }
  }
  /// Grows to n elements, copies of `value`.
  void Resize(std::size_t n, const T& value) {
    Reserve(n);
    for (std::size_t i = size(); i < n; ++i) {
      ::new (static_cast<void*>(&At(i))) T(value);
      size_.store(i + 1);
    }
  }
  /// Destroys the last element (its memory stays, as every block does, so a reader that still
  /// holds its index reads a dead element of a trivially destructible T, never freed memory).
  void PopBack() noexcept {
    const std::size_t n = size() - 1;
    size_.store(n);
    At(n).~T();
  }
  /// Bytes allocated for elements.
  [[nodiscard]] std::size_t bytes() const noexcept { return capacity() * sizeof(T); }

  // std::vector spellings, so that the topology's code reads the same over either container.
  void reserve(std::size_t n) { Reserve(n); }
  void resize(std::size_t n, const T& value) { Resize(n, value); }
  void push_back(const T& value) { EmplaceBack(value); }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    return EmplaceBack(std::forward<Args>(args)...);
  }

 private:
  static constexpr std::size_t Start(std::size_t k) noexcept {
    return kFirst * ((std::size_t{1} << k) - 1);
  }
  T* Block(std::size_t k) const noexcept { return block_[k].load(std::memory_order_acquire); }
  T& At(std::size_t i) noexcept {
    const std::size_t j = i + kFirst;  // block k holds j in [kFirst << k, kFirst << (k + 1))
    const std::size_t k = static_cast<std::size_t>(std::bit_width(j)) - 1 - kFirstLog2;
    return Block(k)[j - (kFirst << k)];
  }
  // Exclusive access (a move): no reader may use either array meanwhile.
  void Swap(StableArray& o) noexcept {
    for (std::size_t k = 0; k < kMaxBlocks; ++k) {
      T* mine = block_[k].load(std::memory_order_relaxed);
      block_[k].store(o.block_[k].load(std::memory_order_relaxed), std::memory_order_relaxed);
      o.block_[k].store(mine, std::memory_order_relaxed);
    }
    std::swap(blocks_, o.blocks_);
    const std::size_t n = size_.load();
    size_.store(o.size_.load());
    o.size_.store(n);
  }

  std::array<std::atomic<T*>, kMaxBlocks> block_{};
  std::size_t blocks_ = 0;
  Published<std::size_t> size_;
};

}  // namespace semgraph::base
