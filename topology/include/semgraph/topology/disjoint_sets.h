// File: semgraph/topology/disjoint_sets.h
//
// DisjointSets: union-find over elements 0 .. n-1 (plain std::uint32_t). The scene graph uses
// it for "which pose tree is a frame in": elements are frame indices, one set per pose tree, so
// the tree-local checks of spec §2 (P3) and §3 (W3, W4) can key per-tree data by the set's
// representative.
//
// Union by size keeps every tree of the structure at most log2(size of its set) high. Find
// (non-const) also halves the path it walks, which only lowers heights. FindConst never writes:
// it is the O(log n) read-only lookup for const and concurrent callers (no path compression
// hidden behind const, unlike LLVM's EquivalenceClasses).
//
// Splitting a set is not supported by union-find itself. When a pose tree is split (a pose edge
// removed), the caller Resets every element of the old set and re-Unions the elements of each
// new tree along its edges: O(size of the trees) calls, each O(1) (Reset) or O(log n) (Union).
//
// Invariants (checked by CheckInvariants):
//  - link(x) is x for a representative, otherwise another element; following links from any x
//    reaches its representative in at most log2(SizeOf(x)) steps (hence no cycles).
//  - SizeOf(representative) is the number of elements whose links lead to it.
//
// Costs (n = size()):
//   AddElement                       O(1) amortized (allocates when the arrays grow)
//   Reset                            O(1)
//   Find, Union                      O(log n) worst case, near O(1) amortized (path halving)
//   FindConst, SameSet, SizeOf       O(log n), noexcept, read-only, no allocation
//   link, size                       O(1)
//   CheckInvariants                  O(n log n), allocates (tests only)
//
// Thread safety: const methods may run concurrently; Find (it halves paths), Union, Reset and
// AddElement need exclusive access.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "semgraph/topology/export.h"

namespace semgraph::topology {

class SEMGRAPH_TOPOLOGY_EXPORT DisjointSets {
 public:
  DisjointSets() = default;

  /// Number of elements.
  [[nodiscard]] std::size_t size() const noexcept { return link_.size(); }

  /// Reserves room for `n` elements in total (growing at least twofold when it grows), so that
  /// AddElement up to n elements does not allocate. On std::bad_alloc the sets are unchanged.
  void Reserve(std::size_t n);

  /// Adds a singleton set {size()} and returns its element (= the old size()).
  /// @pre size() < max uint32 (aborts otherwise).
  std::uint32_t AddElement();

  /// The representative of x's set, halving the path walked (each visited element is relinked
  /// to its grandparent). O(log n). @pre x < size().
  std::uint32_t Find(std::uint32_t x) noexcept;

  /// The representative of x's set, without writing anything. O(log n) by union by size.
  /// @pre x < size().
  [[nodiscard]] std::uint32_t FindConst(std::uint32_t x) const noexcept;

  /// True when a and b are in the same set. Read-only, O(log n). @pre a, b < size().
  [[nodiscard]] bool SameSet(std::uint32_t a, std::uint32_t b) const noexcept {
    return FindConst(a) == FindConst(b);
  }

  /// Merges the sets of a and b (no-op when already one set) and returns the representative of
  /// the merged set: the old representative of the larger set (of a's set on a tie).
  /// O(log n). @pre a, b < size().
  std::uint32_t Union(std::uint32_t a, std::uint32_t b) noexcept;

  /// The number of elements in x's set. O(1) when x is a representative, else O(log n).
  /// @pre x < size().
  [[nodiscard]] std::uint32_t SizeOf(std::uint32_t x) const noexcept {
    return size_[FindConst(x)];
  }

  /// Makes x a singleton again. O(1).
  /// @pre every other element of x's set is Reset too before the structure is used again
  ///      (other members may link through x; resetting only some of them would leave them in
  ///      x's new set with a wrong size). This is the split step described at the top: reset
  ///      the whole old set, then re-Union each new part, O(size of the trees) in total.
  void Reset(std::uint32_t x) noexcept {
    assert(x < size());
    link_[x] = x;
    size_[x] = 1;
  }

  /// The element x links to: x itself for a representative. Exposes the internal forest for
  /// tests and diagnostics (e.g. to see that FindConst writes nothing). @pre x < size().
  [[nodiscard]] std::uint32_t link(std::uint32_t x) const noexcept {
    assert(x < size());
    return link_[x];
  }

  /// Bytes held by the element arrays (their capacity).
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept;

  /// Full check of the invariants listed at the top of this file. For tests and fuzzers.
  [[nodiscard]] bool CheckInvariants() const;

 private:
  std::vector<std::uint32_t> link_;  // the union-find forest: link_[x] == x at representatives
  std::vector<std::uint32_t> size_;  // set size, meaningful at representatives only
};

}  // namespace semgraph::topology
