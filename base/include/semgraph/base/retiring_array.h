// File: semgraph/base/retiring_array.h
//
// RetiringArray<T>: a contiguous growable array for data that one writer changes while readers
// on other threads read it optimistically (the topology's node arrays, name maps and name
// records; docs/realtime.md, "Topology changes while readers run"). Growth copies the elements
// into a larger array and publishes it through an atomic pointer; the old array is retired,
// not freed: it stays allocated until this array dies, so a reader that still holds it reads
// stale but live memory (its validation then fails: growth happens inside a topology change).
//
// Why not StableArray (elements never move): its indexing costs a bit scan and a directory
// load per access, which the query planner's walks pay many times per query; here an access is
// one pointer load and an indexed load, as with std::vector. Elements do move on growth, so it
// suits data whose readers validate (not the edge values, whose addresses compiled queries keep).
//
// Invariants: elements [0, size()) are constructed in the current array; retired arrays hold
// copies of earlier states. T is trivially destructible (retired copies are never destroyed).
// Memory: current capacity plus the retired arrays, at most the current capacity again when
// growth doubles (bytes() reports both). Costs: operator[] O(1); growth O(size) (allocates);
// reserve(n) makes the capacity exactly n when it grows (as std::vector's).
// Thread safety: one writer (reserve, resize, push_back, emplace_back, PopBack, element
// stores); readers may read size() and elements [0, size()) concurrently (their fields atomic,
// e.g. base::Published); what they read is meaningful only under validation.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/base/published.h"

namespace semgraph::base {

template <class T>
class RetiringArray {
  static_assert(std::is_trivially_destructible_v<T>);

 public:
  RetiringArray() noexcept = default;
  RetiringArray(RetiringArray&& o) noexcept { *this = std::move(o); }
  // Exclusive access (no reader of either array meanwhile).
  RetiringArray& operator=(RetiringArray&& o) noexcept {
    blocks_ = std::move(o.blocks_);
    o.blocks_.clear();
    capacity_ = std::exchange(o.capacity_, 0);
    retired_bytes_ = std::exchange(o.retired_bytes_, 0);
    data_ = o.data_.load();
    size_ = o.size_.load();
    o.data_ = nullptr;
    o.size_ = 0;
    return *this;
  }
  RetiringArray(const RetiringArray&) = delete;
  RetiringArray& operator=(const RetiringArray&) = delete;
  ~RetiringArray() = default;

  [[nodiscard]] std::size_t size() const noexcept { return size_.load(); }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  [[nodiscard]] std::size_t capacity() const noexcept { return capacity_; }
  [[nodiscard]] T& operator[](std::size_t i) noexcept { return data_.load()[i]; }
  [[nodiscard]] const T& operator[](std::size_t i) const noexcept { return data_.load()[i]; }
  /// The elements and their count, loaded in the order that keeps them consistent for a reader
  /// (the count first: an array published with a larger count is seen with it), so that a walk
  /// loads the array once.
  struct View {
    const T* data;
    std::size_t size;
  };
  [[nodiscard]] View view() const noexcept {
    const std::size_t n = size();
    return View{data_.load(), n};
  }
  [[nodiscard]] T& back() noexcept { return (*this)[size() - 1]; }
  [[nodiscard]] const T& back() const noexcept { return (*this)[size() - 1]; }

  /// Capacity at least n (exactly n when it grows). On std::bad_alloc nothing changed.
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    if (blocks_.size() == blocks_.capacity()) blocks_.reserve(2 * blocks_.size() + 4);
    std::unique_ptr<Storage[]> grown(new Storage[n]);
    T* to = reinterpret_cast<T*>(grown.get());
    const T* from = data_.load();
    const std::size_t count = size();
    for (std::size_t i = 0; i < count; ++i) ::new (static_cast<void*>(to + i)) T(from[i]);
    data_ = to;  // published (release) after the copies
    retired_bytes_ += capacity_ * sizeof(T);
    capacity_ = n;
    blocks_.push_back(std::move(grown));  // within capacity: cannot throw
  }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    const std::size_t n = size();
    if (n == capacity_) reserve(std::max<std::size_t>(8, 2 * n));
    T* p = ::new (static_cast<void*>(data_.load() + n)) T(std::forward<Args>(args)...);
    size_ = n + 1;
    return *p;
  }
  void push_back(const T& value) { emplace_back(value); }
  /// Grows to n elements, copies of `value` (never shrinks).
  void resize(std::size_t n, const T& value) {
    reserve(n);
    for (std::size_t i = size(); i < n; ++i) {
      ::new (static_cast<void*>(data_.load() + i)) T(value);
      size_ = i + 1;
    }
  }
  /// Drops the last element (its memory stays; a reader holding its index reads a dead copy).
  void PopBack() noexcept { size_ = size() - 1; }
  /// Bytes held: the current array and the retired ones.
  [[nodiscard]] std::size_t bytes() const noexcept {
    return capacity_ * sizeof(T) + retired_bytes_;
  }

 private:
  struct alignas(T) Storage {
    unsigned char bytes[sizeof(T)];
  };
  std::vector<std::unique_ptr<Storage[]>> blocks_;  // every array made; the current one last
  std::size_t capacity_ = 0;
  std::size_t retired_bytes_ = 0;
  Published<T*> data_ = nullptr;
  Published<std::size_t> size_ = 0;
};

}  // namespace semgraph::base
