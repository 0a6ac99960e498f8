// File: semgraph/base/published.h
//
// Published<T>: a field that one writer thread changes while readers on other threads may read
// it (the topology under optimistic one-shot queries, docs/realtime.md "Topology changes while
// readers run"). Every access is atomic: the writer stores with release, readers load with
// acquire. On x86-64 both are plain moves, so the single-threaded cost is the optimizer's
// freedom to merge or drop repeated loads, no more.
//
// Why release/acquire and not relaxed: a reader that validates with a sequence counter (read it,
// read the fields, read it again) needs its field loads ordered before the second counter load,
// and the writer's field stores after its odd counter store. Acquire loads and release stores
// give both orders without standalone fences, which ThreadSanitizer does not model (the pattern
// of seqlock_value.h). A reader that loads a value the writer stored inside a change therefore
// also sees the odd counter, and its validation fails.
//
// Invariants: T is trivially copyable and lock-free as an atomic (4 or 8 bytes here). Copying a
// Published copies the value (a load and a store), so structs of Published fields keep their
// aggregate syntax. Costs: one move per access. Thread safety: one writer; any readers.
#pragma once

#include <atomic>
#include <type_traits>

namespace semgraph::base {

template <class T>
class Published {
  static_assert(std::is_trivially_copyable_v<T>);
  static_assert(std::atomic_ref<T>::is_always_lock_free);

 public:
  Published() noexcept : value_{} {}
  Published(T v) noexcept { Ref().store(v, std::memory_order_release); }  // NOLINT: implicit
  Published(const Published& o) noexcept { Ref().store(o.load(), std::memory_order_release); }
  Published& operator=(const Published& o) noexcept {
    store(o.load());
    return *this;
  }
  Published& operator=(T v) noexcept {
    store(v);
    return *this;
  }
  operator T() const noexcept { return load(); }  // NOLINT: implicit by design

  [[nodiscard]] T load() const noexcept { return Ref().load(std::memory_order_acquire); }
  void store(T v) noexcept { Ref().store(v, std::memory_order_release); }
  // Writer-side read-modify-write (one writer: a load and a store, not an atomic RMW).
  Published& operator+=(T d) noexcept {
    store(static_cast<T>(load() + d));
    return *this;
  }
  Published& operator-=(T d) noexcept {
    store(static_cast<T>(load() - d));
    return *this;
  }
  Published& operator++() noexcept { return *this += T{1}; }
  Published& operator--() noexcept { return *this -= T{1}; }

 private:
  std::atomic_ref<T> Ref() const noexcept { return std::atomic_ref<T>(const_cast<T&>(value_)); }
  alignas(std::atomic_ref<T>::required_alignment) T value_;
};

}  // namespace semgraph::base
