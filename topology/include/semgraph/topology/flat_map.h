// File: semgraph/topology/flat_map.h
//
// FlatMap<V>: an open-addressing hash map from std::uint32_t keys to small trivially copyable
// values, the per-body and per-edge store of the scene graph's topology structures. It exists
// because the query path must be allocation-free and cache-friendly: std::unordered_map
// allocates per node and chases pointers on every lookup.
//
// Layout: one array of {key, value} slots; capacity is a power of two (at least 8); the home
// slot of a key is the high bits of a Fibonacci multiply (key * 2^64/phi), so ids that are
// dense or share low bits still spread; collisions probe linearly. The array is preceded, in
// the same allocation, by a header holding the hash shift, so that one pointer load gives a
// reader a consistent array and capacity.
//
// Invariants:
//  - kEmptyKey (0xFFFFFFFF, the invalid sentinel of the strong ids) marks a free slot and is
//    never a key.
//  - load <= 1/2: size() * 2 <= capacity(), so every probe sequence ends at a free slot.
//  - no tombstones: Erase shifts the following entries of the probe run back (backward-shift
//    deletion), so every key sits between its home slot and the next free slot. Lookups never
//    slow down after erase-heavy phases.
//  - a default-constructed or moved-from map owns no array; the first Insert allocates.
//
// Costs (expected, with the hash spreading keys): Find, Erase O(1); Insert, FindOrInsert O(1)
// amortized (a growth rehashes all entries, O(capacity)); Clear O(capacity), keeps the memory;
// ForEach O(capacity); Reserve(n) O(capacity) when it grows.
//
// Pointers and references: Insert, FindOrInsert and Reserve may rehash, which invalidates every
// pointer and reference into the map. Erase moves entries (backward shift), which invalidates
// them as well. Find never invalidates anything.
//
// Growth by copy, old arrays retired (docs/realtime.md, "Topology changes while readers run"):
// a rehash builds a new array, publishes it through an atomic pointer (base::Published) and
// keeps the old one until the map dies (as base::RetiringArray), so a reader on another
// thread that still walks the old array reads stale but live memory. Keys and the size are
// Published atomics; values are copied as V (a V that readers read while the writer changes
// it must make its fields Published, as TwistForest's records do). Memory: the current array
// plus the retired ones, at most the current capacity again (growth doubles); move assignment
// also retires the destination's arrays. One allocation per growth (the arrays are chained
// through their headers). Single-threaded cost: one pointer load and one load of the header
// per lookup (plain moves on x86-64).
//
// Thread safety: const methods (Find, Contains, size, ForEach on a const map) may run
// concurrently with each other; they never allocate, lock or write. Mutations need one writer;
// readers may run Find/Contains/size concurrently with it, and what they read is meaningful
// only under validation (a change counter read before and after, as SceneTopology's), except
// that a reader never reads freed memory and a probe always ends (bounded by the capacity it
// loaded).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

#include "semgraph/base/demand.h"
#include "semgraph/base/published.h"

namespace semgraph::topology {

template <class V>
class FlatMap {
  // Copied slot by slot, never destroyed in retired arrays: rehash and backward shift copy
  // slots cheaply and never run user code that could throw or reenter. (V must also be default
  // constructible, since free slots hold a V{}; that is asserted in Rehash, because a class
  // nested in the map's owner only becomes default constructible once the owner is complete.)
  static_assert(std::is_trivially_destructible_v<V>, "FlatMap values: trivially destructible");
  static_assert(std::is_nothrow_copy_assignable_v<V>, "FlatMap values: nothrow copyable");

 public:
  /// The key that marks a free slot; it can never be inserted.
  static constexpr std::uint32_t kEmptyKey = 0xFFFFFFFFu;

  FlatMap() noexcept = default;
  FlatMap(const FlatMap& other) { CopyFrom(other); }
  // Copies into our array when it has room (AssignOrAdopt), so repeated assignment does not
  // keep retiring arrays.
  FlatMap& operator=(const FlatMap& other) {
    if (this != &other) {
      FlatMap copy(other);
      AssignOrAdopt(std::move(copy));
    }
    return *this;
  }
  // Moves leave `other` empty and owning no array. The destination's own arrays are retired,
  // not freed, so a reader of the destination never reads freed memory.
  FlatMap(FlatMap&& other) noexcept { *this = std::move(other); }
  FlatMap& operator=(FlatMap&& other) noexcept {
    if (this == &other) return *this;
    // Other's arrays become ours, ahead of our own in the chain (ours stay, retired).
    if (Header* theirs = std::exchange(other.blocks_, nullptr)) {
      Header* oldest = theirs;
      while (oldest->previous != nullptr) oldest = oldest->previous;
      oldest->previous = blocks_;
      blocks_ = theirs;
    }
    table_ = other.table_.load();
    size_ = other.size_.load();
    retired_slots_ += std::exchange(other.retired_slots_, 0) + capacity_;
    capacity_ = std::exchange(other.capacity_, 0);
    other.table_ = nullptr;
    other.size_ = 0;
    return *this;
  }
  /// Makes this map's contents those of `other` without allocating: copied into this map's
  /// current array when it has room for them (other keeps its arrays and frees them when it
  /// dies), else other's arrays are taken over as by a move (ours retired). So a map assigned
  /// to repeatedly retires an array only when it grows, and its memory stays within twice its
  /// largest capacity (a plain move would retire ours every time). other is left valid.
  void AssignOrAdopt(FlatMap&& other) noexcept {
    if (this == &other) return;
    if (capacity_ < 2 * other.size() || capacity_ == 0) {
      *this = std::move(other);
      return;
    }
    Clear();
    other.ForEach([this](std::uint32_t key, const V& value) {
      bool inserted = false;
      Emplace(key, value, &inserted);  // within capacity: no rehash, no allocation
    });
  }
  ~FlatMap() {
    for (Header* h = blocks_; h != nullptr;) {
      Header* previous = h->previous;
      ::operator delete(static_cast<void*>(h));
      h = previous;
    }
  }

  /// The value stored under `key`, or nullptr. O(1) expected; noexcept, allocation-free.
  [[nodiscard]] const V* Find(std::uint32_t key) const noexcept {
    const Slot* table = table_.load();
    if (table == nullptr || key == kEmptyKey) return nullptr;
    const Slot& slot = table[Probe(table, key)];
    return slot.key.load() == key ? &slot.value : nullptr;
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
    Slot* table = table_.load();
    if (table == nullptr || key == kEmptyKey) return false;
    std::size_t hole = Probe(table, key);
    if (table[hole].key.load() != key) return false;
    // Backward shift: walk the rest of the probe run; an entry may move into the hole iff its
    // home slot is not cyclically inside (hole, j], i.e. its probe distance reaches the hole.
    const std::size_t mask = capacity_ - 1;
    const int shift = Shift(table);
    for (std::size_t j = Next(hole, mask); table[j].key.load() != kEmptyKey; j = Next(j, mask)) {
      const std::size_t home = Home(table[j].key.load(), shift);
      if (((j - home) & mask) >= ((j - hole) & mask)) {
        table[hole] = table[j];
        hole = j;
      }
    }
    table[hole] = Slot{};
    size_ = size_ - 1;
    return true;
  }

  [[nodiscard]] std::size_t size() const noexcept { return size_.load(); }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  /// Number of slots (0 before the first insert). Writer thread.
  [[nodiscard]] std::size_t capacity() const noexcept { return capacity_; }

  /// Removes every entry and keeps the memory, so refilling to the same size does not allocate.
  void Clear() noexcept {
    Slot* table = table_.load();
    for (std::size_t i = 0; i < capacity_; ++i) table[i] = Slot{};
    size_ = 0;
  }

  /// Makes room for `n` entries in total, so that inserting up to `n` keys does not allocate.
  void Reserve(std::size_t n) {
    const std::size_t wanted = std::bit_ceil(n < kMinCapacity / 2 ? kMinCapacity : 2 * n);
    if (wanted > capacity_) Rehash(wanted);
  }

  /// Calls f(key, value) for every entry, in slot order (deterministic for a given history,
  /// otherwise unspecified). f must not insert into or erase from this map. Writer thread (or
  /// readers without a writer).
  template <class F>
  void ForEach(F&& f) {
    Slot* table = table_.load();
    for (std::size_t i = 0; i < capacity_; ++i) {
      const std::uint32_t key = table[i].key.load();
      if (key != kEmptyKey) f(key, table[i].value);
    }
  }
  template <class F>
  void ForEach(F&& f) const {
    const Slot* table = table_.load();
    for (std::size_t i = 0; i < capacity_; ++i) {
      const std::uint32_t key = table[i].key.load();
      if (key != kEmptyKey) f(key, table[i].value);
    }
  }

  /// Heap bytes owned (current and retired arrays) plus the object itself.
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    std::size_t headers = 0;
    for (const Header* h = blocks_; h != nullptr; h = h->previous) headers += kHeaderBytes;
    return sizeof(*this) + headers + (capacity_ + retired_slots_) * sizeof(Slot);
  }

 private:
  struct Slot {
    base::Published<std::uint32_t> key = kEmptyKey;
    V value{};
  };
  // Each array is one allocation: this header, then the slots. The header is written before
  // the array is published and never changes, so readers read it plainly.
  struct Header {
    Header* previous;  // the next older array owned by this map (a chain, newest first)
    int shift;         // 64 - log2(capacity): the hash shift of this array
  };
  static_assert(alignof(Slot) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
  static constexpr std::size_t kHeaderBytes =
      (sizeof(Header) + alignof(Slot) - 1) / alignof(Slot) * alignof(Slot);
  static constexpr std::size_t kMinCapacity = 8;

  [[nodiscard]] static const Header* HeaderOf(const Slot* table) noexcept {
    return reinterpret_cast<const Header*>(reinterpret_cast<const unsigned char*>(table) -
                                           kHeaderBytes);
  }
  [[nodiscard]] static int Shift(const Slot* table) noexcept { return HeaderOf(table)->shift; }
  [[nodiscard]] static std::size_t Next(std::size_t i, std::size_t mask) noexcept {
    return (i + 1) & mask;
  }
  // High bits of a 64-bit Fibonacci multiply: every key bit influences the home slot.
  [[nodiscard]] static std::size_t Home(std::uint32_t key, int shift) noexcept {
    return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> shift);
  }

  // Index of `key`'s slot, or of the free slot that ends its probe run. Ends after at most
  // capacity steps even if a concurrent writer left no free slot in what this reader sees.
  [[nodiscard]] static std::size_t Probe(const Slot* table, std::uint32_t key) noexcept {
    const int shift = Shift(table);
    const std::size_t mask = (std::size_t{1} << (64 - shift)) - 1;
    std::size_t i = Home(key, shift);
    for (std::size_t steps = 0; steps <= mask; ++steps) {
      const std::uint32_t k = table[i].key.load();
      if (k == key || k == kEmptyKey) return i;
      i = Next(i, mask);
    }
    return i;  // a full run without the key: its slot holds another key, so "absent"
  }

  V& Emplace(std::uint32_t key, const V& value, bool* inserted) {
    SEMGRAPH_DEMAND(key != kEmptyKey);
    if (Slot* table = table_.load()) {
      const std::size_t i = Probe(table, key);
      if (table[i].key.load() == key) return table[i].value;
    }
    // Grow before placing, so the load stays <= 1/2 after the insert.
    const std::size_t n = size_.load();
    if (2 * (n + 1) > capacity_) Rehash(capacity_ == 0 ? kMinCapacity : 2 * capacity_);
    Slot* table = table_.load();
    Slot& slot = table[Probe(table, key)];
    slot.value = value;  // before the key: a reader that finds the key finds the value
    slot.key = key;
    size_ = n + 1;
    *inserted = true;
    return slot.value;
  }

  // capacity is a power of two >= kMinCapacity and > 2 * size_. The new array is filled, then
  // published; the old one is retired (kept). Strong guarantee on std::bad_alloc.
  void Rehash(std::size_t capacity) {
    static_assert(std::is_default_constructible_v<V>, "FlatMap values need a default value");
    void* raw = ::operator new(kHeaderBytes + capacity * sizeof(Slot));
    const int shift = 64 - std::countr_zero(capacity);
    Header* header = ::new (raw) Header{blocks_, shift};
    Slot* grown = reinterpret_cast<Slot*>(static_cast<unsigned char*>(raw) + kHeaderBytes);
    for (std::size_t i = 0; i < capacity; ++i) ::new (static_cast<void*>(grown + i)) Slot();
    const std::size_t mask = capacity - 1;
    const Slot* old = table_.load();
    for (std::size_t j = 0; j < capacity_; ++j) {
      const std::uint32_t key = old[j].key.load();
      if (key == kEmptyKey) continue;
      std::size_t i = Home(key, shift);
      while (grown[i].key.load() != kEmptyKey) i = Next(i, mask);
      grown[i] = old[j];
    }
    blocks_ = header;
    table_ = grown;  // published (release) after the copies
    retired_slots_ += capacity_;
    capacity_ = capacity;
  }

  void CopyFrom(const FlatMap& other) {
    if (other.capacity_ == 0) return;
    Rehash(other.capacity_);  // same capacity and shift: slots keep their positions
    const Slot* from = other.table_.load();
    Slot* to = table_.load();
    for (std::size_t i = 0; i < capacity_; ++i) to[i] = from[i];
    size_ = other.size_.load();
  }

  Header* blocks_ = nullptr;  // every array owned (current and retired), newest first
  std::size_t capacity_ = 0;  // of the current array (writer thread)
  std::size_t retired_slots_ = 0;
  base::Published<Slot*> table_ = nullptr;  // the current array's slots (past its header)
  base::Published<std::size_t> size_ = 0;
};

}  // namespace semgraph::topology
