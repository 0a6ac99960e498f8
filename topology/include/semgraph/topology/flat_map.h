// File: semgraph/topology/flat_map.h
//
// FlatMap<V>: an open-addressing hash map from std::uint32_t keys to small trivially copyable
// values, the per-body and per-edge store of the scene graph's topology structures. It exists
// because the query path must be allocation-free and cache-friendly: std::unordered_map
// allocates per node and chases pointers on every lookup.
//
// Layout: one array of {key, value} slots; capacity is a power of two (at least 8); the home
// slot of a key is the high bits of a Fibonacci multiply (key * 2^64/phi), so ids that are
// dense or share low bits still spread; collisions probe linearly.
//
// Invariants:
//  - kEmptyKey (0xFFFFFFFF, the invalid sentinel of the strong ids) marks a free slot and is
//    never a key.
//  - load <= 1/2: size() * 2 <= capacity(), so every probe sequence ends at a free slot.
//  - no tombstones: Erase shifts the following entries of the probe run back (backward-shift
//    deletion), so every key sits between its home slot and the next free slot. Lookups never
//    slow down after erase-heavy phases.
//  - a default-constructed or moved-from map owns no memory; the first Insert allocates.
//
// Costs (expected, with the hash spreading keys): Find, Erase O(1); Insert, FindOrInsert O(1)
// amortized (a growth rehashes all entries, O(capacity)); Clear O(capacity), keeps the memory;
// ForEach O(capacity); Reserve(n) O(capacity) when it grows.
//
// Pointers and references: Insert, FindOrInsert and Reserve may rehash, which invalidates every
// pointer and reference into the map. Erase moves entries (backward shift), which invalidates
// them as well. Find never invalidates anything.
//
// Thread safety: const methods (Find, Contains, size, ForEach on a const map) may run
// concurrently; they never allocate, lock or write. Any mutation needs exclusive access.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

template <class V>
class FlatMap {
  // Trivially copyable: rehash and backward shift copy slots cheaply and never run user code
  // that could throw or reenter. (V must also be default constructible, since free slots hold
  // a V{}; that is asserted in Rehash, because a class nested in the map's owner only becomes
  // default constructible once the owner is complete.)
  static_assert(std::is_trivially_copyable_v<V>, "FlatMap values must be trivially copyable");

 public:
  /// The key that marks a free slot; it can never be inserted.
  static constexpr std::uint32_t kEmptyKey = 0xFFFFFFFFu;

  FlatMap() noexcept = default;
  FlatMap(const FlatMap&) = default;
  FlatMap& operator=(const FlatMap&) = default;
  // Moves leave `other` empty and owning no memory (std::vector's moved-from state is only
  // "valid but unspecified" for assignment, so exchange explicitly).
  FlatMap(FlatMap&& other) noexcept
      : slots_(std::exchange(other.slots_, {})),
        size_(std::exchange(other.size_, 0)),
        shift_(std::exchange(other.shift_, 64)) {}
  FlatMap& operator=(FlatMap&& other) noexcept {
    slots_ = std::exchange(other.slots_, {});
    size_ = std::exchange(other.size_, 0);
    shift_ = std::exchange(other.shift_, 64);
    return *this;
  }
  ~FlatMap() = default;

  /// The value stored under `key`, or nullptr. O(1) expected; noexcept, allocation-free.
  [[nodiscard]] const V* Find(std::uint32_t key) const noexcept {
    if (slots_.empty() || key == kEmptyKey) return nullptr;
    const Slot& slot = slots_[Probe(key)];
    return slot.key == key ? &slot.value : nullptr;
  }
  [[nodiscard]] V* Find(std::uint32_t key) noexcept {
    return const_cast<V*>(std::as_const(*this).Find(key));
  }
  [[nodiscard]] bool Contains(std::uint32_t key) const noexcept { return Find(key) != nullptr; }

  /// Inserts `value` under `key` and returns it.
  /// @pre key != kEmptyKey and key is absent (checked; aborts otherwise: the probe that finds
  /// the free slot passes over the key if it is present, so the check is free).
  V& Insert(std::uint32_t key, const V& value) {
    bool inserted = false;
    V& stored = Emplace(key, value, &inserted);
    SEMGRAPH_DEMAND(inserted);
    return stored;
  }

  /// The value under `key`, inserting `default_value` first when absent.
  /// @pre key != kEmptyKey.
  V& FindOrInsert(std::uint32_t key, const V& default_value) {
    bool inserted = false;
    return Emplace(key, default_value, &inserted);
  }

  /// Removes `key`; returns whether it was present. O(1) expected; never allocates or shrinks.
  bool Erase(std::uint32_t key) noexcept {
    if (slots_.empty() || key == kEmptyKey) return false;
    std::size_t hole = Probe(key);
    if (slots_[hole].key != key) return false;
    // Backward shift: walk the rest of the probe run; an entry may move into the hole iff its
    // home slot is not cyclically inside (hole, j], i.e. its probe distance reaches the hole.
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t j = (hole + 1) & mask; slots_[j].key != kEmptyKey; j = (j + 1) & mask) {
      const std::size_t home = Home(slots_[j].key);
      if (((j - home) & mask) >= ((j - hole) & mask)) {
        slots_[hole] = slots_[j];
        hole = j;
      }
    }
    slots_[hole] = Slot{};
    --size_;
    return true;
  }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
  /// Number of slots (0 before the first insert).
  [[nodiscard]] std::size_t capacity() const noexcept { return slots_.size(); }

  /// Removes every entry and keeps the memory, so refilling to the same size does not allocate.
  void Clear() noexcept {
    for (Slot& slot : slots_) slot = Slot{};
    size_ = 0;
  }

  /// Makes room for `n` entries in total, so that inserting up to `n` keys does not allocate.
  void Reserve(std::size_t n) {
    const std::size_t wanted = std::bit_ceil(n < kMinCapacity / 2 ? kMinCapacity : 2 * n);
    if (wanted > slots_.size()) Rehash(wanted);
  }

  /// Calls f(key, value) for every entry, in slot order (deterministic for a given history,
  /// otherwise unspecified). f must not insert into or erase from this map.
  template <class F>
  void ForEach(F&& f) {
    for (Slot& slot : slots_) {
      if (slot.key != kEmptyKey) f(slot.key, slot.value);
    }
  }
  template <class F>
  void ForEach(F&& f) const {
    for (const Slot& slot : slots_) {
      if (slot.key != kEmptyKey) f(slot.key, slot.value);
    }
  }

  /// Heap bytes owned plus the object itself.
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    return sizeof(*this) + slots_.capacity() * sizeof(Slot);
  }

 private:
  struct Slot {
    std::uint32_t key = kEmptyKey;
    V value{};
  };
  static constexpr std::size_t kMinCapacity = 8;

  // High bits of a 64-bit Fibonacci multiply: every key bit influences the home slot.
  [[nodiscard]] std::size_t Home(std::uint32_t key) const noexcept {
    return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  // Index of `key`'s slot, or of the free slot that ends its probe run. Requires slots.
  [[nodiscard]] std::size_t Probe(std::uint32_t key) const noexcept {
    const std::size_t mask = slots_.size() - 1;
    std::size_t i = Home(key);
    while (slots_[i].key != key && slots_[i].key != kEmptyKey) i = (i + 1) & mask;
    return i;
  }

  V& Emplace(std::uint32_t key, const V& value, bool* inserted) {
    SEMGRAPH_DEMAND(key != kEmptyKey);
    if (!slots_.empty()) {
      const std::size_t i = Probe(key);
      if (slots_[i].key == key) return slots_[i].value;
    }
    // Grow before placing, so the load stays <= 1/2 after the insert.
    if (2 * (size_ + 1) > slots_.size()) {
      Rehash(slots_.empty() ? kMinCapacity : 2 * slots_.size());
    }
    Slot& slot = slots_[Probe(key)];
    slot.key = key;
    slot.value = value;
    ++size_;
    *inserted = true;
    return slot.value;
  }

  // capacity is a power of two >= kMinCapacity and > 2 * size_.
  void Rehash(std::size_t capacity) {
    static_assert(std::is_default_constructible_v<V>, "FlatMap values need a default value");
    std::vector<Slot> old(capacity);
    old.swap(slots_);
    shift_ = 64 - std::countr_zero(capacity);
    const std::size_t mask = capacity - 1;
    for (const Slot& slot : old) {
      if (slot.key == kEmptyKey) continue;
      std::size_t i = Home(slot.key);
      while (slots_[i].key != kEmptyKey) i = (i + 1) & mask;
      slots_[i] = slot;
    }
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
  int shift_ = 64;  // 64 - log2(capacity); unused while slots_ is empty
};

}  // namespace semgraph::topology
